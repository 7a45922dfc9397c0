//! `pushlab simulate` from the outside: the files it writes, the truth it records, and its refusals.

#![allow(clippy::unwrap_used)]

use crate::cli_common;

use std::path::PathBuf;

use cli_common::{pushlab, temp_dir};

/// A folder that does not exist yet, in a fresh temporary folder: where `simulate --out` writes.
fn new_set_dir(name: &str) -> PathBuf {
    temp_dir("pushlab-cli-sim", name).join("set")
}

#[test]
fn simulate_writes_a_set_with_the_true_com_and_h_and_refuses_to_overwrite_it() {
    let dir = new_set_dir("set");
    let out = dir.to_str().unwrap();
    let args = [
        "simulate",
        "--out",
        out,
        "--box",
        "0.2x0.3",
        "--com-offset",
        "0.02,-0.03",
        "--pressure",
        "rim",
        "--pushes",
        "2",
        "--push-angles",
        "-10,10",
        "--rate",
        "4",
        "--duration",
        "5",
        "--seed",
        "3",
    ];
    let first = pushlab(&args);
    assert_eq!(first.code, 0, "{}", first.stderr);
    let (set, errors) = pushlab_core::recording::read_set(&dir).unwrap();
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(set.setting.com_offset, Some([0.02, -0.03]));
    assert!(set.setting.h.unwrap() > 0.05);
    assert_eq!(set.recordings.len(), 4);
    // Two pushes spread over the middle 80 % of the 0.3 m front face, each at both angles.
    let offsets: Vec<Option<f64>> = set
        .setting
        .trajectories
        .iter()
        .map(|t| t.contact_offset)
        .collect();
    assert_eq!(offsets, [-0.12, -0.12, 0.12, 0.12].map(Some));
    let csv = std::fs::read_to_string(dir.join("push_000.csv")).unwrap();
    assert!(csv.starts_with("time,robot_x,robot_y,object_x,object_y,object_theta\n"));
    assert_eq!(csv.lines().count(), 1 + 21);

    let again = pushlab(&args);
    assert_eq!(again.code, 1);
    let stderr = &again.stderr;
    assert!(
        stderr.contains("already holds a recording set; pass --overwrite"),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn simulate_names_the_bad_parameter() {
    let dir = new_set_dir("bad");
    let out = dir.to_str().unwrap();
    // Exit 2 for a value clap refuses (the documented code of wrong arguments), 1 for a set that
    // cannot be simulated.
    let run = |extra: &[&str], code: i32| {
        let mut args = vec!["simulate", "--out", out];
        args.extend_from_slice(extra);
        let output = pushlab(&args);
        assert_eq!(output.code, code, "{}", output.stderr);
        output.stderr
    };
    let wood = run(&["--pressure", "wood"], 2);
    assert!(
        wood.contains("invalid value 'wood' for '--pressure <PRESSURE>'")
            && wood.contains("[possible values: uniform, rim, centre, feet]"),
        "{wood}"
    );
    let up = run(&["--side", "up"], 2);
    assert!(
        up.contains("[possible values: front, left, back, right]"),
        "{up}"
    );
    assert!(
        run(&["--contact-offsets", "0.5"], 1)
            .contains("contact offset 0.5 m is off the front face")
    );
    let by = run(&["--box", "0.3by0.4"], 2);
    assert!(
        by.contains("for '--box <WxL>': expected WIDTHxLENGTH in metres, e.g. 0.3x0.4"),
        "{by}"
    );
    assert!(
        run(&["--box=-0.3x0.4"], 2).contains("the width '-0.3' is not a number of metres above 0")
    );
    assert!(!dir.exists(), "a refused command wrote files");
}
