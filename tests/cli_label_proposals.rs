//! `pushlab simulate --truth-labels`, `pushlab labels propose` and `pushlab labels compare` from the
//! outside, on a small simulated set: the files they write, the scores, and their refusals.

#![allow(clippy::unwrap_used)]

use crate::cli_common;

use std::path::Path;

use cli_common::{pushlab, temp_dir};

const PREFIX: &str = "pushlab-cli-proposals";

/// A slippery box pushed at ±30° and 0°: sticking and slipping both occur. 3 pushes of 101 frames.
fn simulate(dir: &Path) {
    let run = pushlab(&[
        "simulate",
        "--out",
        dir.to_str().unwrap(),
        "--pushes",
        "1",
        "--push-angles=-30,0,30",
        "--pusher-friction",
        "0.2",
        "--truth-labels",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
}

/// Every file of `dir` with its bytes, to check that nothing of the set changed.
fn contents(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).unwrap())
        })
        .collect();
    files.sort();
    files
}

#[test]
fn proposals_on_a_simulated_set_agree_with_its_truth_and_leave_the_set_alone() {
    let root = temp_dir(PREFIX, "agree");
    let set = root.join("set");
    simulate(&set);
    let truth = set.join("truth-labels.json");
    let text = std::fs::read_to_string(&truth).unwrap();
    assert!(text.contains("\"format\": \"pushlab-labels\""), "{text}");
    for name in ["push_000.csv", "push_001.csv", "push_002.csv"] {
        assert!(text.contains(name), "{name} in {text}");
    }
    let before = contents(&set);

    let proposed = root.join("proposed.json");
    let run = pushlab(&[
        "labels",
        "propose",
        set.to_str().unwrap(),
        "--out",
        proposed.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("push_000.csv"), "{}", run.stdout);
    assert!(run.stdout.contains("wrote "), "{}", run.stdout);
    assert_eq!(contents(&set), before, "the set's files are only read");

    let report = root.join("compare.json");
    let run = pushlab(&[
        "labels",
        "compare",
        truth.to_str().unwrap(),
        proposed.to_str().unwrap(),
        "--json",
        report.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.starts_with("label "), "{}", run.stdout);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let labels = json["labels"].as_array().unwrap();
    let get = |name: &str| {
        labels
            .iter()
            .find(|l| l["label"] == name)
            .unwrap_or_else(|| panic!("{name} in {json}"))
    };
    for field in ["precision", "recall", "f1", "frames_truth", "frames_other"] {
        assert!(get("contact").get(field).is_some(), "{field}");
    }
    // Three pushes of 101 frames, nearly all in contact; the proposals find it.
    let contact = get("contact");
    let frames_truth = contact["frames_truth"].as_u64().unwrap();
    assert!((250..=303).contains(&frames_truth), "{contact}");
    assert!(contact["f1"].as_f64().unwrap() >= 0.9, "{contact}");
    // Both contact modes occur in the truth and are found more often than not.
    for mode in ["sticking", "slipping"] {
        let m = get(mode);
        assert!(m["frames_truth"].as_u64().unwrap() > 0, "{m}");
        assert!(m["f1"].as_f64().unwrap() >= 0.6, "{m}");
    }
    // No bad tracking in a simulation without glitches: nothing to score, and nothing proposed.
    let bad = get("bad tracking");
    assert_eq!(bad["frames_truth"], 0);
    assert_eq!(bad["frames_other"], 0);
    assert!(bad["f1"].is_null(), "{bad}");
}

#[test]
fn propose_refuses_to_write_over_the_sets_own_files() {
    let root = temp_dir(PREFIX, "refuse");
    let set = root.join("set");
    simulate(&set);
    let before = contents(&set);
    for target in ["pushlab-labels.json", "push_001.csv", "setting.json"] {
        let out = set.join(target);
        let run = pushlab(&[
            "labels",
            "propose",
            set.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(run.code, 1, "{target}: {}", run.stdout);
        assert!(
            run.stderr.contains("an input of the proposals"),
            "{target}: {}",
            run.stderr
        );
    }
    assert_eq!(contents(&set), before);
    let run = pushlab(&[
        "labels",
        "propose",
        root.join("missing").to_str().unwrap(),
        "--out",
        root.join("p.json").to_str().unwrap(),
    ]);
    assert_eq!(run.code, 1);
    assert!(
        run.stderr.contains("no recording could be loaded from"),
        "{}",
        run.stderr
    );
}

#[test]
fn compare_names_the_file_and_field_of_bad_input() {
    let root = temp_dir(PREFIX, "bad");
    let good = root.join("good.json");
    std::fs::write(
        &good,
        r#"{"format": "pushlab-labels", "version": 1,
            "recordings": {"a.csv": {"segments": [{"label": "contact", "start": 0, "end": 10}]}}}"#,
    )
    .unwrap();
    let cases = [
        (
            "not-json.json",
            "{\"format\": ",
            "not-json.json: line 1, column 11: EOF while parsing a value",
        ),
        (
            "unknown.json",
            r#"{"format": "pushlab-labels", "version": 1,
                "recordings": {"a.csv": {"segments": [{"label": "touching", "start": 0, "end": 5}]}}}"#,
            "unknown.json: recordings.\"a.csv\".segments[0].label: unknown label \"touching\"",
        ),
        (
            "other-set.json",
            r#"{"format": "pushlab-labels", "version": 1,
                "recordings": {"b.csv": {"segments": [{"label": "contact", "start": 0, "end": 5}]}}}"#,
            "other-set.json: recordings: none of the reference's recordings (a.csv) is labelled, found only b.csv",
        ),
    ];
    for (name, text, expected) in cases {
        let path = root.join(name);
        std::fs::write(&path, text).unwrap();
        let run = pushlab(&[
            "labels",
            "compare",
            good.to_str().unwrap(),
            path.to_str().unwrap(),
        ]);
        assert_eq!(run.code, 1, "{name}: {}", run.stdout);
        assert!(run.stderr.contains(expected), "{name}: {}", run.stderr);
    }
    // An empty reference is refused rather than scored.
    let empty = root.join("empty.json");
    std::fs::write(&empty, r#"{"format": "pushlab-labels", "version": 1}"#).unwrap();
    let run = pushlab(&[
        "labels",
        "compare",
        empty.to_str().unwrap(),
        good.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 1);
    assert!(
        run.stderr
            .contains("empty.json: recordings: no frame of any range label"),
        "{}",
        run.stderr
    );
    // A file that is not there: said once, with why.
    let missing = root.join("missing.json");
    let run = pushlab(&[
        "labels",
        "compare",
        missing.to_str().unwrap(),
        good.to_str().unwrap(),
    ]);
    assert_eq!(run.code, 1);
    assert_eq!(
        run.stderr.trim_end(),
        format!(
            "pushlab: cannot read labels file {}: No such file or directory (os error 2)",
            missing.display()
        )
    );
}
