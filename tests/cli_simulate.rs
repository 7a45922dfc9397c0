//! `pushlab simulate` from the outside: the files it writes, the truth it records, and its refusals.

#![allow(clippy::unwrap_used)]

use crate::cli_common;

use std::path::PathBuf;

use cli_common::{pushlab, temp_dir};
use pushlab_core::recording::read_set;
use pushlab_core::sandbox::mystery::SANDBOX_NOISE;
use pushlab_core::sandbox::{Mystery, MysteryObject, PointerPath, Sandbox, recorded_pushes};

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

/// A drag from the sandbox's start through the box's front face, as the page's hook takes one.
fn a_drag(seed: u64, noise: bool) -> (pushlab_core::sandbox::Sandbox, PointerPath) {
    let mystery = Mystery::draw(seed, MysteryObject::Box).unwrap();
    let sandbox = Sandbox::new(mystery, noise.then_some(SANDBOX_NOISE));
    let start = sandbox.pusher();
    let path = PointerPath::from_points(&[
        [start.x, start.y, 0.0],
        [start.x + 0.2, start.y - 0.03, 5.0],
        [start.x + 0.26, start.y - 0.05, 7.0],
    ])
    .unwrap();
    (sandbox, path)
}

#[test]
fn a_sandbox_drag_replayed_writes_the_sandboxs_poses_to_the_bit_with_the_truth() {
    for noise in [false, true] {
        let (mut sandbox, path) = a_drag(12, noise);
        let made = recorded_pushes(&sandbox.drag(path.clone()).unwrap());
        let dir = new_set_dir(if noise { "sandbox-noise" } else { "sandbox" });
        let drag = dir.with_file_name("drag.csv");
        std::fs::create_dir_all(dir.parent().unwrap()).unwrap();
        std::fs::write(&drag, path.to_csv()).unwrap();
        let mut args = vec![
            "simulate",
            "--sandbox",
            "12",
            "--object",
            "box",
            "--pointer-path",
            drag.to_str().unwrap(),
            "--out",
            dir.to_str().unwrap(),
        ];
        if noise {
            args.push("--tracking-noise");
        }
        let run = pushlab(&args);
        assert_eq!(run.code, 0, "{}", run.stderr);
        let (set, problems) = read_set(&dir).unwrap();
        assert!(problems.is_empty(), "{problems:?}");
        assert_eq!(set.recordings.len(), 1);
        assert_eq!(*set.recordings[0].trajectory, made[0], "noise {noise}");
        let truth = sandbox.mystery().hidden.com_offset;
        assert_eq!(set.setting.com_offset, Some(truth));
        assert_eq!(set.setting.h, Some(sandbox.mystery().h));
        // The pusher's path written beside it replays the same push again.
        let again = dir.with_file_name("again");
        let pusher_path = dir.join("push_000.pusher-path.csv");
        let mut args = vec![
            "simulate",
            "--sandbox",
            "12",
            "--pointer-path",
            pusher_path.to_str().unwrap(),
            "--out",
            again.to_str().unwrap(),
        ];
        if noise {
            args.push("--tracking-noise");
        }
        assert_eq!(pushlab(&args).code, 0);
        assert_eq!(
            *read_set(&again).unwrap().0.recordings[0].trajectory,
            made[0]
        );
    }
}

#[test]
fn a_bad_pointer_path_is_refused_naming_its_line_and_field() {
    let dir = new_set_dir("sandbox-bad");
    let drag = dir.with_file_name("drag.csv");
    std::fs::create_dir_all(dir.parent().unwrap()).unwrap();
    std::fs::write(&drag, "t,x,y\n0,-0.4,0\n1,oops,0\n").unwrap();
    let run = pushlab(&[
        "simulate",
        "--sandbox",
        "1",
        "--pointer-path",
        drag.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_ne!(run.code, 0);
    assert!(
        run.stderr.contains(&format!(
            "{} line 3: x is 'oops', expected a finite number",
            drag.display()
        )),
        "{}",
        run.stderr
    );
    let run = pushlab(&[
        "simulate",
        "--sandbox",
        "1",
        "--object",
        "sphere",
        "--pointer-path",
        drag.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        run.stderr
            .contains("unknown mystery object 'sphere': expected box, t or ellipse"),
        "{}",
        run.stderr
    );
}
