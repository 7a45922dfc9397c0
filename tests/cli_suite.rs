//! `pushlab suite` and `--model-kind` end to end: the built binary on a small suite over the sample
//! data; the table and the JSON report, the same numbers on one worker and on two, bad specs refused
//! with the file and what is wrong (exit 2), and the model kind chosen, recorded and checked.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::cli_common;
use cli_common::pushlab;

fn temp_dir(name: &str) -> PathBuf {
    cli_common::temp_dir("pushlab-suite", name)
}

fn sample_set(set: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join(set)
        .display()
        .to_string()
}

/// Two small experiments: the same setting online (a control) and the box pushed on another face.
fn small_suite(dir: &Path) -> PathBuf {
    let spec = serde_json::json!({
        "horizon": 2,
        "epochs": 3,
        "seed": 1,
        "models": ["contact", "paper"],
        "physics": true,
        "experiments": [
            {
                "name": "control",
                "offline": [format!("{}/offline_00?.csv", sample_set("box1-paper-center-front"))],
                "online": [format!("{}/online_000.csv", sample_set("box1-paper-center-front")),
                           format!("{}/online_001.csv", sample_set("box1-paper-center-front")),
                           format!("{}/online_001.csv", sample_set("box1-paper-center-front"))]
            },
            {
                "name": "other face",
                "offline": [format!("{}/offline_00?.csv", sample_set("box1-paper-center-front"))],
                "online": [format!("{}/online_00?.csv", sample_set("box1-paper-center-left"))],
                "horizon": 1
            }
        ]
    });
    let path = dir.join("suite.json");
    std::fs::write(&path, serde_json::to_vec_pretty(&spec).unwrap()).unwrap();
    path
}

/// The report without its timings, which differ from run to run.
fn without_timings(mut v: Value) -> Value {
    fn strip(v: &mut Value) {
        match v {
            Value::Object(map) => {
                map.remove("seconds");
                map.remove("workers");
                map.values_mut().for_each(strip);
            }
            Value::Array(items) => items.iter_mut().for_each(strip),
            _ => {}
        }
    }
    strip(&mut v);
    v
}

#[test]
fn a_suite_prints_one_table_and_gives_the_same_numbers_on_one_worker_and_on_two() {
    let dir = temp_dir("table");
    let spec = small_suite(&dir);
    let spec_s = spec.display().to_string();
    let (one, two) = (dir.join("one.json"), dir.join("two.json"));
    let (one_s, two_s) = (one.display().to_string(), two.display().to_string());

    let (md, tex) = (dir.join("table.md"), dir.join("table.tex"));
    let (md_s, tex_s) = (md.display().to_string(), tex.display().to_string());
    let run = pushlab(&[
        "suite",
        &spec_s,
        "--jobs",
        "2",
        "--json",
        &two_s,
        "--markdown",
        &md_s,
        "--latex",
        &tex_s,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    paper_tables_hold_the_reports_numbers(&two, &md, &tex);
    let lines: Vec<&str> = run.stdout.lines().collect();
    let header = lines
        .iter()
        .find(|l| l.starts_with("NMSE pos/rot"))
        .unwrap_or_else(|| panic!("no header:\n{}", run.stdout));
    for column in ["contact", "paper", "physics only"] {
        assert!(header.contains(column), "{header}");
    }
    for row in ["control", "other face"] {
        let line = lines
            .iter()
            .find(|l| l.starts_with(row))
            .unwrap_or_else(|| panic!("no row {row}:\n{}", run.stdout));
        // Two kinds × offline, fixed, online, physics fixed, online and weighted: nine pos/rot cells.
        let cells = line.split_whitespace().filter(|c| c.contains('/')).count();
        assert_eq!(cells, 9, "{line}");
    }
    assert!(run.stdout.contains("2 experiment(s) in"), "{}", run.stdout);
    assert!(run.stdout.contains(&format!("wrote {two_s}")));

    let run = pushlab(&["suite", &spec_s, "--jobs", "1", "--json", &one_s]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let read =
        |p: &Path| -> Value { serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap() };
    let (a, b) = (read(&one), read(&two));
    assert_eq!(a["workers"], 1);
    assert_eq!(b["workers"], 2);
    assert_eq!(without_timings(a.clone()), without_timings(b));

    let experiments = a["experiments"].as_array().unwrap();
    assert_eq!(experiments[0]["name"], "control");
    // The wildcard took offline_000 … offline_009; the two online paths name online_001 twice,
    // which is used once.
    assert_eq!(experiments[0]["offline_recordings"], 10);
    assert_eq!(experiments[0]["online_recordings"], 2);
    assert_eq!(experiments[0]["horizon"], 2);
    assert_eq!(experiments[1]["horizon"], 1);
    for e in experiments {
        let models = e["models"].as_array().unwrap();
        let names: Vec<&str> = models
            .iter()
            .map(|m| m["model"].as_str().unwrap())
            .collect();
        assert_eq!(names, ["contact", "paper"]);
        for m in models {
            for pass in ["offline", "fixed", "online"] {
                let pos = m[pass]["pos"].as_f64().unwrap();
                assert!(pos.is_finite() && pos > 0.0, "{pass}: {m}");
            }
        }
        let physics = &e["physics"]["online"]["pos"];
        assert!(physics.as_f64().unwrap() > 0.0, "{e}");
        assert!(e["errors"].as_array().unwrap().is_empty(), "{e}");
    }
    // On another face the contact model stays near its offline loss; the paper's network, fed
    // inputs it never saw, does not.
    let other = &experiments[1]["models"];
    let online_pos = |i: usize| other[i]["online"]["pos"].as_f64().unwrap();
    assert!(
        online_pos(0) < online_pos(1),
        "contact {} vs paper {}",
        online_pos(0),
        online_pos(1)
    );

    // --models replaces the spec's list, ablations included.
    let ablations = dir.join("ablations.json");
    let ablations_s = ablations.display().to_string();
    let run = pushlab(&[
        "suite",
        &spec_s,
        "--models",
        "contact-prior-only,paper-augmented",
        "--json",
        &ablations_s,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let header = run.stdout.lines().find(|l| l.starts_with("NMSE")).unwrap();
    assert!(
        header.contains("contact-prior-only") && header.contains("paper-augmented"),
        "{header}"
    );
    let v = read(&ablations);
    assert_eq!(
        v["spec"]["models"],
        serde_json::json!(["contact-prior-only", "paper-augmented"])
    );
    let run = pushlab(&["suite", &spec_s, "--models", "contact,lynch"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("unknown model \"lynch\"; expected one of contact"),
        "{}",
        run.stderr
    );
}

#[test]
fn a_bad_spec_is_refused_with_its_file_and_what_is_wrong() {
    let dir = temp_dir("bad");
    let cases: [(&str, &str); 4] = [
        ("{\"experiments\": []}", "\"experiments\" is empty"),
        (
            "{\"experiments\": [{\"name\": \"a\", \"offline\": [\"x\"], \"online\": [\"y\"]}],\n \"modles\": []}",
            "line 2, column",
        ),
        (
            "{\"models\": [\"contact\", \"bogus\"], \"experiments\": [{\"name\": \"a\", \"offline\": [\"x\"], \"online\": [\"y\"]}]}",
            "bogus",
        ),
        (
            "{\"experiments\": [{\"name\": \"a\", \"offline\": [], \"online\": [\"y\"]}]}",
            "experiments[0] (\"a\"): \"offline\" and \"online\" each need at least one path",
        ),
    ];
    for (i, (text, expected)) in cases.iter().enumerate() {
        let path = dir.join(format!("bad-{i}.json"));
        std::fs::write(&path, text).unwrap();
        let run = pushlab(&["suite", &path.display().to_string()]);
        assert_eq!(run.code, 2, "case {i}: {}", run.stderr);
        assert!(
            run.stderr.contains(&format!("bad-{i}.json")) && run.stderr.contains(expected),
            "case {i}: expected {expected:?} in {}",
            run.stderr
        );
    }
    let run = pushlab(&["suite", &dir.join("missing.json").display().to_string()]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("missing.json"), "{}", run.stderr);

    // Paths that match nothing leave the experiment without data: exit 1, the experiment named.
    let path = dir.join("nothing.json");
    std::fs::write(
        &path,
        "{\"epochs\": 1, \"experiments\": [{\"name\": \"empty\", \"offline\": [\"no-such-*.csv\"], \"online\": [\"no-such-*.csv\"]}]}",
    )
    .unwrap();
    let run = pushlab(&["suite", &path.display().to_string()]);
    assert_eq!(run.code, 1, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr
            .contains("1 experiment(s) could not run completely: empty ("),
        "{}",
        run.stderr
    );
}

#[test]
fn the_model_kind_is_chosen_recorded_and_checked() {
    let dir = temp_dir("kind");
    let files: Vec<String> = (0..4)
        .map(|i| {
            format!(
                "{}/offline_00{i}.csv",
                sample_set("box1-paper-center-front")
            )
        })
        .collect();
    let train = |kind: Option<&str>, out: &Path| {
        let out_s = out.display().to_string();
        let mut args = vec!["train", "--data"];
        args.extend(files.iter().map(String::as_str));
        args.extend(["--epochs", "1", "--horizon", "2", "--out", &out_s]);
        if let Some(kind) = kind {
            args.extend(["--model-kind", kind]);
        }
        pushlab(&args)
    };
    let kind_of = |path: &Path| -> String {
        let v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        assert_eq!(v["version"], 3);
        v["kind"].as_str().unwrap().to_owned()
    };

    let default = dir.join("default.json");
    let run = train(None, &default);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("(contact model)"), "{}", run.stdout);
    assert_eq!(kind_of(&default), "contact");

    let paper = dir.join("paper.json");
    let run = train(Some("paper"), &paper);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(run.stdout.contains("(paper model)"), "{}", run.stdout);
    assert_eq!(kind_of(&paper), "paper");

    let run = train(Some("lynch"), &dir.join("never.json"));
    assert_eq!(run.code, 2);
    assert!(
        run.stderr
            .contains("unknown model kind \"lynch\"; expected one of contact, paper"),
        "{}",
        run.stderr
    );
    assert!(!dir.join("never.json").exists());

    // eval with a model file takes its kind; naming another kind is a contradiction.
    let online = format!("{}/online_000.csv", sample_set("box1-paper-center-front"));
    let paper_s = paper.display().to_string();
    let json = dir.join("eval.json");
    let json_s = json.display().to_string();
    let run = pushlab(&[
        "eval",
        "--offline",
        &files[0],
        "--online",
        &online,
        "--model",
        &paper_s,
        "--json",
        &json_s,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let report: Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(report["config"]["kind"], "paper");
    let run = pushlab(&[
        "eval",
        "--offline",
        &files[0],
        "--online",
        &online,
        "--model",
        &paper_s,
        "--model-kind",
        "contact",
    ]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(
        run.stderr
            .contains("--model-kind contact differs from the kind of the model file (paper)"),
        "{}",
        run.stderr
    );
}

/// Issue 26: a set simulated at the default 0.05 m/s with 2 mm tracking noise at 50 Hz was read as
/// pushing at 0.15–0.22 m/s (frame-to-frame noise summed as motion), so a model trained at the same
/// speed at 10 Hz warned about the speed. It still differs in frame rate, and says only that.
#[test]
fn a_noisy_set_at_a_higher_rate_is_not_read_as_faster_pushes() {
    let dir = temp_dir("noisy-rate");
    let simulate = |name: &str, rate: &str| {
        let out = dir.join(name).display().to_string();
        let run = pushlab(&[
            "simulate",
            "--out",
            &out,
            "--rate",
            rate,
            "--duration",
            "4",
            "--pushes",
            "2",
        ]);
        assert_eq!(run.code, 0, "{}", run.stderr);
        out
    };
    let (slow, fast) = (simulate("at-10-hz", "10"), simulate("at-50-hz", "50"));
    let trained = dir.join("model.json").display().to_string();
    let run = pushlab(&[
        "train",
        "--data",
        &slow,
        "--horizon",
        "1",
        "--epochs",
        "1",
        "--out",
        &trained,
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let default = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/default-model.json")
        .display()
        .to_string();
    for model in [&trained, &default] {
        let warning = domain_warning(model, &slow, &fast);
        assert!(
            warning.contains("frames at 10 Hz")
                && warning.contains("here have frames at 50 Hz:")
                && !warning.contains("pushes at"),
            "{model}: {warning}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `pushlab eval --model MODEL --offline OFFLINE --online ONLINE` (which must succeed) and its
/// "the model was trained on …" warning line.
fn domain_warning(model: &str, offline: &str, online: &str) -> String {
    let run = pushlab(&[
        "eval",
        "--model",
        model,
        "--offline",
        offline,
        "--online",
        online,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    run.stderr
        .lines()
        .find(|l| l.starts_with("warning: the model was trained on"))
        .unwrap_or_else(|| panic!("no warning in:\n{}", run.stderr))
        .to_string()
}

#[test]
fn eval_warns_when_the_online_recordings_lie_outside_the_model_s_domain() {
    let dir = temp_dir("domain");
    let small = dir.join("small-rod");
    let small_s = small.display().to_string();
    // A 0.1 m box pushed by a 5 mm rod at 50 Hz: far from the sample data's boxes and 175 mm disc.
    let run = pushlab(&[
        "simulate",
        "--out",
        &small_s,
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
        "2",
        "--seed",
        "4",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let model = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets/default-model.json")
        .display()
        .to_string();
    let offline = format!("{}/offline_000.csv", sample_set("box1-paper-center-front"));
    let warning = domain_warning(&model, &offline, &small_s);
    assert!(
        warning.contains("objects of 0.40–0.55 m")
            && warning.contains("a pusher radius of 175.0 mm")
            && warning.contains("frames at 10 Hz")
            && warning.contains(
                "here have objects of 0.10 m, a pusher radius of 5.0 mm, frames at 50 Hz"
            ),
        "{warning}"
    );

    // Recordings like the model's own: no warning.
    let online = format!("{}/online_000.csv", sample_set("box2-plastic-center-front"));
    let run = pushlab(&[
        "eval",
        "--model",
        &model,
        "--offline",
        &offline,
        "--online",
        &online,
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(!run.stderr.contains("warning:"), "{}", run.stderr);
}

#[test]
fn carry_theta_in_a_suite_goes_on_from_push_to_push_as_eval_does() {
    let dir = temp_dir("carry");
    let set = sample_set("box1-paper-center-front");
    let offline = format!("{set}/offline_00?.csv");
    let online = [
        format!("{set}/online_000.csv"),
        format!("{set}/online_001.csv"),
    ];
    let suite = |carry: bool| -> Value {
        let spec = serde_json::json!({
            "horizon": 2, "epochs": 3, "seed": 1, "models": ["contact"], "physics": false,
            "carry_theta": carry,
            "experiments": [{"name": "two pushes", "offline": [offline], "online": online}]
        });
        let (spec_path, out) = (
            dir.join(format!("suite-{carry}.json")),
            dir.join(format!("out-{carry}.json")),
        );
        std::fs::write(&spec_path, serde_json::to_vec(&spec).unwrap()).unwrap();
        let run = pushlab(&[
            "suite",
            &spec_path.display().to_string(),
            "--json",
            &out.display().to_string(),
        ]);
        assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
    };
    let online_nmse = |v: &Value| v["experiments"][0]["models"][0]["online"].clone();
    let (alone, carried) = (suite(false), suite(true));
    assert_eq!(carried["spec"]["carry_theta"], true);
    assert_ne!(online_nmse(&alone), online_nmse(&carried));

    // The same training and online pushes through eval --carry-theta give the same numbers.
    let report = dir.join("eval.json");
    let offline_files: Vec<String> = (0..10)
        .map(|i| format!("{set}/offline_00{i}.csv"))
        .collect();
    let mut args = vec!["eval", "--offline"];
    args.extend(offline_files.iter().map(String::as_str));
    args.extend([
        "--online",
        &online[0],
        &online[1],
        "--horizon",
        "2",
        "--epochs",
        "3",
        "--seed",
        "1",
        "--carry-theta",
        "--json",
    ]);
    let report_s = report.display().to_string();
    args.push(&report_s);
    let run = pushlab(&args);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    let eval: Value = serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(eval["trajectories"][1]["continued"], true);
    assert_eq!(eval["online"], online_nmse(&carried));
}

/// The Markdown and LaTeX tables: one row per experiment holding the report's NMSE to three
/// decimals, in the terminal table's column order, the lowest online ones in bold, booktabs rules.
fn paper_tables_hold_the_reports_numbers(report: &Path, md: &Path, tex: &Path) {
    let report: Value = serde_json::from_str(&std::fs::read_to_string(report).unwrap()).unwrap();
    let (md, tex) = (
        std::fs::read_to_string(md).unwrap(),
        std::fs::read_to_string(tex).unwrap(),
    );
    let md_lines: Vec<&str> = md.lines().filter(|l| l.starts_with('|')).collect();
    assert_eq!(
        md_lines[0],
        "| Experiment | contact offline | contact fixed | contact online | paper offline | paper fixed | paper online | physics only fixed | physics only online | weighted online |"
    );
    assert_eq!(md_lines.len(), 4, "header, rule, two rows:\n{md}");
    assert!(
        tex.contains("\\begin{tabular}{lccccccccc}\n\\toprule"),
        "{tex}"
    );
    assert!(tex.contains("\\multicolumn{3}{c}{contact} & \\multicolumn{3}{c}{paper} & \\multicolumn{2}{c}{physics only} & \\multicolumn{1}{c}{weighted}"), "{tex}");
    assert!(
        tex.contains(
            "\\cmidrule(lr){2-4} \\cmidrule(lr){5-7} \\cmidrule(lr){8-9} \\cmidrule(lr){10-10}"
        ),
        "{tex}"
    );
    assert!(
        tex.contains("\\midrule") && tex.trim_end().ends_with("\\bottomrule\n\\end{tabular}"),
        "{tex}"
    );
    let plain = |s: &str| {
        s.replace("**", "")
            .replace("\\textbf{", "")
            .replace('}', "")
    };
    for (i, experiment) in report["experiments"].as_array().unwrap().iter().enumerate() {
        let name = experiment["name"].as_str().unwrap();
        let pair = |n: &Value| {
            format!(
                "{:.3} / {:.3}",
                n["pos"].as_f64().unwrap(),
                n["rot"].as_f64().unwrap()
            )
        };
        let mut cells = Vec::new();
        for model in experiment["models"].as_array().unwrap() {
            cells.extend(["offline", "fixed", "online"].map(|k| pair(&model[k])));
        }
        cells.extend(["fixed", "online", "weighted"].map(|k| pair(&experiment["physics"][k])));
        assert_eq!(
            plain(md_lines[2 + i]),
            format!("| {name} | {} |", cells.join(" | ")),
            "{md}"
        );
        let tex_row = (tex.lines())
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("no row {name}:\n{tex}"));
        assert_eq!(
            plain(tex_row),
            format!("{name} & {} \\\\", cells.join(" & "))
        );
        // The lowest online position NMSE of the row is the bold one.
        let online: Vec<f64> = (experiment["models"].as_array().unwrap().iter())
            .map(|m| m["online"]["pos"].as_f64().unwrap())
            .chain(
                ["online", "weighted"].map(|k| experiment["physics"][k]["pos"].as_f64().unwrap()),
            )
            .collect();
        let best = online.iter().copied().fold(f64::INFINITY, f64::min);
        assert!(
            md_lines[2 + i].contains(&format!("**{best:.3}** /")),
            "{}",
            md_lines[2 + i]
        );
        assert!(
            tex_row.contains(&format!("\\textbf{{{best:.3}}} /")),
            "{tex_row}"
        );
    }
}
