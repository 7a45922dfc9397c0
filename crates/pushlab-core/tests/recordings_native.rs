//! Native recording sets: write → read round trips, error messages, folders of sets.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};

use pushlab_core::geometry::Pose2;
use pushlab_core::recording::native::{parse_csv, parse_setting};
use pushlab_core::recording::{
    NativeError, ObjectShape, PushSide, Setting, TrajectoryEntry, WriteError, load_paths, read_set,
    write_set,
};
use pushlab_core::trajectory::{Frame, Trajectory};

const HEADER: &str = "time,robot_x,robot_y,object_x,object_y,object_theta";

/// A fresh empty folder under the target dir's temp area, unique per test.
fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pushlab-rec-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

fn setting(files: &[&str]) -> Setting {
    let json = serde_json::json!({
        "name": "box-test",
        "object": {"shape": "box", "width": 0.09, "length": 0.12},
        "pusher_radius": 0.005,
        "material": "plywood",
        "floor_friction": 0.3,
        "pusher_friction": 0.25,
        "com_offset": [0.01, -0.02],
        "h": 0.031,
        "push_side": "front",
        "sample_rate_hz": 100.0,
        "robot_model": "UR5e",
        "calibration": {"date": "2024-01-02", "ok": true},
        "trajectories": files.iter().map(|f| serde_json::json!({
            "file": f, "contact_offset": 0.01, "push_angle_deg": -10.0, "operator": "kim"
        })).collect::<Vec<_>>(),
    });
    serde_json::from_value(json).expect("valid setting")
}

/// Awkward numbers: irrational-looking values, tiny and huge magnitudes, negative zero.
fn trajectory(seed: f64, n: usize) -> Trajectory {
    Trajectory::new(
        (0..n)
            .map(|i| {
                let t = i as f64 * 0.01 + seed / 3.0;
                Frame {
                    time: t,
                    robot: [t.sin() * 0.1 + 1e-17, -0.0 + (t * 7.0).cos() / 3.0].into(),
                    object: Pose2::new(1.0 / 3.0 + t * 1e-3, 2.0f64.sqrt() * t, 0.7 * t * seed),
                }
            })
            .collect(),
    )
}

#[test]
fn write_then_read_gives_bit_identical_values_and_keeps_unknown_keys() {
    let dir = temp_dir("roundtrip").join("nested").join("set");
    let setting = setting(&["traj_000.csv", "traj_001.csv"]);
    let trajectories = [trajectory(1.0, 50), trajectory(2.0, 7)];
    write_set(&dir, &setting, &trajectories).expect("write");

    let (set, errors) = read_set(&dir).expect("read");
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(
        *set.setting, setting,
        "setting.json must round-trip exactly"
    );
    assert_eq!(set.setting.extra["robot_model"], "UR5e");
    assert_eq!(set.setting.extra["calibration"]["ok"], true);
    assert_eq!(set.setting.trajectories[1].extra["operator"], "kim");
    assert_eq!(set.setting.push_side, Some(PushSide::Front));
    assert_eq!(set.recordings.len(), 2);
    for (recording, written) in set.recordings.iter().zip(&trajectories) {
        assert!(recording.warnings.is_empty());
        assert_eq!(recording.trajectory.len(), written.len());
        for (a, b) in recording.trajectory.frames.iter().zip(&written.frames) {
            let bits = |f: &Frame| {
                [
                    f.time,
                    f.robot.x,
                    f.robot.y,
                    f.object.position.x,
                    f.object.position.y,
                    f.object.yaw,
                ]
                .map(f64::to_bits)
            };
            assert_eq!(bits(a), bits(b));
        }
    }
    assert_eq!(set.recordings[0].name, "traj_000");
    assert_eq!(
        set.recordings[1].entry.as_ref().map(|e| e.file.as_str()),
        Some("traj_001.csv")
    );
    // No temporary files are left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 3, "{names:?}");
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
}

#[test]
fn rewriting_a_set_replaces_files_whole() {
    let dir = temp_dir("rewrite");
    let setting = setting(&["a.csv"]);
    write_set(&dir, &setting, &[trajectory(1.0, 100)]).unwrap();
    write_set(&dir, &setting, &[trajectory(3.0, 3)]).unwrap();
    let (set, _) = read_set(&dir).unwrap();
    assert_eq!(*set.recordings[0].trajectory, trajectory(3.0, 3));
}

#[test]
fn write_refuses_what_the_reader_would_refuse() {
    let dir = temp_dir("write-errors");
    let err = write_set(&dir, &setting(&["a.csv", "b.csv"]), &[trajectory(1.0, 5)]).unwrap_err();
    assert!(matches!(
        err,
        WriteError::CountMismatch {
            entries: 2,
            trajectories: 1
        }
    ));
    assert_eq!(
        err.to_string(),
        "setting.json lists 2 trajectories but 1 were given"
    );

    let err = write_set(&dir, &setting(&["../evil.csv"]), &[trajectory(1.0, 5)]).unwrap_err();
    assert!(matches!(err, WriteError::BadFileName(_)), "{err}");

    let mut t = trajectory(1.0, 5);
    t.frames[3].object.yaw = f64::NAN;
    let err = write_set(&dir, &setting(&["a.csv"]), &[t]).unwrap_err();
    assert_eq!(
        err.to_string(),
        "trajectory 'a.csv' frame 3: object_theta is NaN, expected a finite number"
    );
    let mut t = trajectory(1.0, 5);
    t.frames[2].time = t.frames[1].time;
    let err = write_set(&dir, &setting(&["a.csv"]), &[t]).unwrap_err();
    assert!(err.to_string().contains("frame 2: time"), "{err}");
    assert!(
        !dir.join("setting.json").exists(),
        "nothing written on error"
    );
}

fn csv_error(text: &str) -> String {
    parse_csv(text.as_bytes(), Path::new("traj_003.csv"))
        .expect_err("should be refused")
        .to_string()
}

#[test]
fn csv_errors_name_file_line_field_and_expectation() {
    let mut text = format!("{HEADER}\n");
    for i in 0..15 {
        text.push_str(&format!("{},0,0,0,0,0\n", i as f64 * 0.1));
    }
    text.push_str("1.5,0,0,0,0,nan\n"); // line 17
    assert_eq!(
        csv_error(&text),
        "traj_003.csv line 17: object_theta is 'nan', expected a finite number"
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n0,0,0,0,0,0\n0.1,0,abc,0,0,0\n")),
        "traj_003.csv line 3: robot_y is 'abc', expected a number"
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n0,0,0,0,0,0\n0.1,0,0,1e999,0,0\n")),
        "traj_003.csv line 3: object_x is '1e999', expected a finite number"
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n0,0,0,0,0\n")),
        format!("traj_003.csv line 2: 5 fields, expected 6 ({HEADER})")
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n0,0,0,0,0,0\n0,0,0,0,0,0\n")),
        "traj_003.csv line 3: time 0 is not after the previous row's 0, expected strictly increasing time"
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n1,0,0,0,0,0\n0.5,0,0,0,0,0\n")),
        "traj_003.csv line 3: time 0.5 is not after the previous row's 1, expected strictly increasing time"
    );
    assert_eq!(
        csv_error("t,x,y\n0,0,0\n"),
        format!("traj_003.csv line 1: header is 't,x,y', expected `{HEADER}`")
    );
    assert_eq!(
        csv_error(""),
        format!("traj_003.csv line 1: the file is empty, expected the header `{HEADER}`")
    );
    assert_eq!(
        csv_error(&format!("{HEADER}\n0,0,0,0,0,0\n")),
        "traj_003.csv line 3: only 1 data rows, expected at least 2"
    );
    assert!(csv_error(&format!("{HEADER}\n0,0,0,0,0,0\n0.1,\u{ff}x,0,0,0,0\n")).contains("line 3"));
}

#[test]
fn csv_accepts_crlf_bom_spaces_and_unwraps_theta_with_a_warning() {
    let text = format!(
        "\u{feff}{HEADER}\r\n0, 1, 2, 3, 4, 3.1\r\n0.1,1,2,3,4,-3.1\r\n0.2,1,2,3,4,-3.0\r\n\r\n"
    );
    let parsed = parse_csv(text.as_bytes(), Path::new("x.csv")).expect("loads");
    let thetas: Vec<f64> = parsed
        .trajectory
        .frames
        .iter()
        .map(|f| f.object.yaw)
        .collect();
    assert_eq!(thetas[0], 3.1);
    assert!(
        (thetas[1] - (2.0 * std::f64::consts::PI - 3.1)).abs() < 1e-12,
        "{thetas:?}"
    );
    assert!((thetas[2] - (2.0 * std::f64::consts::PI - 3.0)).abs() < 1e-12);
    assert_eq!(parsed.notes.len(), 1);
    assert!(parsed.notes[0].contains("1 time(s)"), "{:?}", parsed.notes);
}

#[test]
fn setting_errors_name_the_field() {
    let path = Path::new("set/setting.json");
    let err = parse_setting(br#"{"name": "x", "object": {"shape": "box", "width": -1, "length": 0.1}, "pusher_radius": 0.01}"#, path)
        .unwrap_err();
    assert!(
        matches!(err, NativeError::SettingField { ref field, .. } if field == "object"),
        "{err}"
    );
    assert!(
        err.to_string()
            .starts_with("set/setting.json: field `object`: a box needs"),
        "{err}"
    );

    let err = parse_setting(
        br#"{"name": "x", "object": {"shape": "box", "width": 1, "length": 1}}"#,
        path,
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("missing field `pusher_radius`"),
        "{err}"
    );

    let err = parse_setting(br#"{"name": "x", "object": {"shape": "box", "width": 1, "length": 1}, "pusher_radius": 0.01, "trajectories": [{"file": "../../etc/passwd.csv"}]}"#, path)
        .unwrap_err();
    assert!(
        err.to_string().contains("field `trajectories[0].file`"),
        "{err}"
    );

    // A non-convex polygon loads; one that crosses itself is refused, naming the field and edges.
    let notched = parse_setting(br#"{"name": "x", "object": {"shape": "polygon", "vertices": [[0,0],[2,0],[1,0.5],[2,2],[0,2]]}, "pusher_radius": 0.01}"#, path)
        .expect("a simple non-convex outline loads");
    assert!(!notched.object.outline().unwrap().is_convex());
    let err = parse_setting(br#"{"name": "x", "object": {"shape": "polygon", "vertices": [[0,0],[2,2],[2,0],[0,2]]}, "pusher_radius": 0.01}"#, path)
        .unwrap_err();
    assert!(
        err.to_string().ends_with(
            "field `object.vertices`: edges 0 and 2 touch or cross; an outline must go round once \
             without meeting itself, expected a simple counter-clockwise outline"
        ),
        "{err}"
    );
    let err = parse_setting(br#"{"name": "x", "object": {"shape": "polygon", "vertices": [[0,0],[0,1],[1,0]]}, "pusher_radius": 0.01}"#, path)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("field `object.vertices`: the outline's vertices go clockwise"),
        "{err}"
    );

    // The Push-T T by name, at the default millimetre per pixel or a given scale.
    let t = parse_setting(br#"{"name": "x", "object": {"shape": "preset", "preset": "push-t"}, "pusher_radius": 0.015}"#, path)
        .expect("the T loads");
    let outline = t.object.outline().unwrap();
    assert!((outline.area() - 0.0063).abs() < 1e-12);
    let t = parse_setting(br#"{"name": "x", "object": {"shape": "preset", "preset": "push-t", "metres_per_px": 0.002}, "pusher_radius": 0.03}"#, path)
        .expect("the T loads");
    assert!((t.object.outline().unwrap().size() - 0.24).abs() < 1e-12);
    let err = parse_setting(br#"{"name": "x", "object": {"shape": "preset", "preset": "push-x"}, "pusher_radius": 0.01}"#, path)
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("field `object.preset`: unknown preset 'push-x', expected one of: push-t"),
        "{err}"
    );
    let err = parse_setting(br#"{"name": "x", "object": {"shape": "preset", "preset": "push-t", "metres_per_px": -1}, "pusher_radius": 0.01}"#, path)
        .unwrap_err();
    assert!(
        err.to_string().contains("field `object.metres_per_px`: a preset's scale must be a positive finite number of metres per unit, got -1"),
        "{err}"
    );

    let err = parse_setting(b"{\"name\": \"x\",\n \"object\": ", path).unwrap_err();
    assert!(err.to_string().contains("line 2, column"), "{err}");

    // A polygon setting with unknown keys loads.
    let ok = parse_setting(br#"{"name": "x", "object": {"shape": "polygon", "vertices": [[0,0],[1,0],[0,1]], "colour": "red"}, "pusher_radius": 0.01, "future": [1,2]}"#, path)
        .expect("loads");
    assert!(matches!(ok.object, ObjectShape::Polygon { .. }));
    assert_eq!(ok.extra["future"], serde_json::json!([1, 2]));
    assert_eq!(ok.com_offset, None);
}

#[test]
fn a_folder_of_sets_opens_as_many_sets_and_reports_bad_files() {
    let root = temp_dir("folder-of-sets");
    write_set(
        &root.join("b-set"),
        &setting(&["t0.csv", "t1.csv"]),
        &[trajectory(1.0, 10), trajectory(2.0, 10)],
    )
    .unwrap();
    write_set(
        &root.join("a-set"),
        &setting(&["only.csv"]),
        &[trajectory(1.0, 4)],
    )
    .unwrap();
    write_set(
        &root.join("deeper/c-set"),
        &setting(&["t.csv"]),
        &[trajectory(1.0, 4)],
    )
    .unwrap();
    // A set whose second CSV is broken and whose third is missing.
    let broken = root.join("d-broken");
    write_set(
        &broken,
        &setting(&["good.csv", "bad.csv"]),
        &[trajectory(1.0, 4), trajectory(1.0, 4)],
    )
    .unwrap();
    std::fs::write(
        broken.join("bad.csv"),
        format!("{HEADER}\n0,0,0,0,0,0\n0.1,0,0,0,0\n"),
    )
    .unwrap();
    // A set with an unusable setting.json.
    std::fs::create_dir_all(root.join("e-badsetting")).unwrap();
    std::fs::write(root.join("e-badsetting/setting.json"), "{").unwrap();
    // Junk that is not a recording is ignored while searching a folder.
    std::fs::write(root.join("notes.txt"), "hello").unwrap();
    std::fs::write(root.join("other.json"), "{}").unwrap();

    let report = load_paths(std::slice::from_ref(&root));
    let dirs: Vec<String> = report
        .sets
        .iter()
        .map(|s| s.dir.strip_prefix(&root).unwrap().display().to_string())
        .collect();
    assert_eq!(dirs, ["a-set", "b-set", "d-broken", "deeper/c-set"]);
    assert_eq!(report.recording_count(), 1 + 2 + 1 + 1);
    let errors: Vec<String> = report.errors.iter().map(ToString::to_string).collect();
    assert_eq!(errors.len(), 2, "{errors:?}");
    assert!(errors[0].ends_with("d-broken/bad.csv line 3: 5 fields, expected 6 (time,robot_x,robot_y,object_x,object_y,object_theta)"), "{errors:?}");
    assert!(
        errors[1].contains("e-badsetting/setting.json: not a valid setting.json"),
        "{errors:?}"
    );
}

#[test]
fn single_csv_setting_json_and_missing_paths() {
    let root = temp_dir("single");
    let set = root.join("set");
    write_set(
        &set,
        &setting(&["t0.csv", "t1.csv"]),
        &[trajectory(1.0, 10), trajectory(2.0, 6)],
    )
    .unwrap();

    let report = load_paths(&[set.join("t1.csv")]);
    assert!(report.errors.is_empty());
    assert_eq!(report.sets.len(), 1);
    assert_eq!(report.sets[0].recordings.len(), 1);
    assert_eq!(report.sets[0].recordings[0].trajectory.len(), 6);
    assert_eq!(
        report.sets[0].recordings[0].entry.as_ref().unwrap().file,
        "t1.csv"
    );

    let report = load_paths(&[set.join("setting.json"), set.clone()]);
    assert_eq!(report.recording_count(), 2, "the same set is loaded once");

    std::fs::remove_file(set.join("t0.csv")).unwrap();
    let report = load_paths(std::slice::from_ref(&set));
    assert_eq!(report.recording_count(), 1);
    assert_eq!(
        report.errors[0].to_string(),
        format!(
            "{}: listed in setting.json but the file does not exist",
            set.join("t0.csv").display()
        )
    );

    std::fs::write(
        root.join("loose.csv"),
        format!("{HEADER}\n0,0,0,0,0,0\n1,0,0,0,0,0\n"),
    )
    .unwrap();
    std::fs::write(root.join("x.txt"), "text").unwrap();
    let report = load_paths(&[
        root.join("loose.csv"),
        root.join("nope"),
        root.join("x.txt"),
    ]);
    let errors: Vec<String> = report.errors.iter().map(ToString::to_string).collect();
    assert!(
        errors[0].ends_with(
            "loose.csv: no setting.json in the same folder, expected a native recording set"
        ),
        "{errors:?}"
    );
    assert!(errors[1].contains("nope: cannot read"), "{errors:?}");
    assert!(
        errors[2].contains("x.txt: not a recording: expected a native set folder"),
        "{errors:?}"
    );

    let empty = temp_dir("empty");
    let report = load_paths(std::slice::from_ref(&empty));
    assert!(report.errors[0].to_string().contains("no recordings found"));
}

#[test]
fn a_set_listing_no_trajectories_loads_every_csv() {
    let dir = temp_dir("unlisted");
    write_set(
        &dir,
        &setting(&["b.csv", "a.csv"]),
        &[trajectory(1.0, 3), trajectory(2.0, 4)],
    )
    .unwrap();
    let mut s = setting(&[]);
    s.trajectories = Vec::<TrajectoryEntry>::new();
    write_set(&dir, &s, &[]).unwrap();
    let (set, errors) = read_set(&dir).unwrap();
    assert!(errors.is_empty());
    let names: Vec<&str> = set.recordings.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(names, ["a", "b"]);
    assert!(set.recordings.iter().all(|r| r.entry.is_none()));
}

#[test]
fn loading_never_modifies_input_files() {
    let dir = temp_dir("readonly");
    write_set(&dir, &setting(&["t.csv"]), &[trajectory(1.0, 10)]).unwrap();
    // A CSV with a wrapped angle is unwrapped in memory only.
    let text = format!("{HEADER}\n0,0,0,0,0,3.1\n0.1,0,0,0,0,-3.1\n");
    std::fs::write(dir.join("t.csv"), &text).unwrap();
    let before = std::fs::metadata(dir.join("t.csv"))
        .unwrap()
        .modified()
        .unwrap();
    let report = load_paths(std::slice::from_ref(&dir));
    // Unwrapping loses nothing: a note, not a warning.
    let recording = &report.sets[0].recordings[0];
    assert_eq!((recording.warnings.len(), recording.notes.len()), (0, 1));
    assert_eq!(std::fs::read_to_string(dir.join("t.csv")).unwrap(), text);
    assert_eq!(
        std::fs::metadata(dir.join("t.csv"))
            .unwrap()
            .modified()
            .unwrap(),
        before
    );
}
