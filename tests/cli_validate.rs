//! `pushlab validate` end to end: the built binary on the real MIT files (skipped when absent), on a
//! broken file and with wrong arguments; output lines and exit codes.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::skip;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn validate(args: &[&Path]) -> (i32, Vec<String>) {
    let Output { status, stdout, .. } = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .arg("validate")
        .args(args)
        .output()
        .expect("run pushlab");
    let lines = String::from_utf8(stdout)
        .expect("utf-8 output")
        .lines()
        .map(str::to_string)
        .collect();
    (status.code().expect("exit code"), lines)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("pushlab-cli-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn real_mit_files_validate_with_one_line_each() {
    let Some(dir) = skip::shared(Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push") else {
        return;
    };
    let (code, lines) = validate(&[&dir]);
    assert_eq!(code, 0, "{lines:#?}");
    assert_eq!(lines.len(), 5, "{lines:#?}");
    let rect1 = lines
        .iter()
        .find(|l| l.contains("shape=rect1"))
        .expect("a line for rect1");
    // A pose row dropped is a warning; its frozen force sensor, which pushlab does not read, a note.
    assert!(
        rect1.starts_with("1 warning: ") && rect1.contains("1 row(s) out of order dropped"),
        "{rect1}"
    );
    assert!(rect1.contains(" — notes: ft_wrench is frozen"), "{rect1}");
    assert_eq!(
        lines[4],
        "4 recording(s) loaded (1 with warnings, 1 with notes), 0 error(s)"
    );
}

#[test]
fn broken_and_good_files_give_exit_1_and_a_line_each() {
    let dir = temp_dir("broken");
    let set = dir.join("set");
    std::fs::create_dir_all(&set).unwrap();
    std::fs::write(
        set.join("setting.json"),
        r#"{"name": "t", "object": {"shape": "box", "width": 0.1, "length": 0.1}, "pusher_radius": 0.005,
            "trajectories": [{"file": "good.csv"}, {"file": "traj_003.csv"}]}"#,
    )
    .unwrap();
    let header = "time,robot_x,robot_y,object_x,object_y,object_theta\n";
    std::fs::write(
        set.join("good.csv"),
        format!("{header}0,0,0,0.1,0,0\n0.5,0.01,0,0.11,0,0\n"),
    )
    .unwrap();
    std::fs::write(
        set.join("traj_003.csv"),
        format!("{header}0,0,0,0,0,0\n0.1,0,0,0,0,nan\n"),
    )
    .unwrap();

    let (code, lines) = validate(&[&set]);
    assert_eq!(code, 1, "{lines:#?}");
    assert_eq!(
        lines,
        [
            format!("ok: {} (2 frames, 0.50 s)", set.join("good.csv").display()),
            format!(
                "error: {} line 3: object_theta is 'nan', expected a finite number",
                set.join("traj_003.csv").display()
            ),
            "1 recording(s) loaded (0 with warnings), 1 error(s)".to_string(),
        ]
    );

    // The good file alone: exit 0.
    let (code, lines) = validate(&[&set.join("good.csv")]);
    assert_eq!(code, 0, "{lines:#?}");

    // A missing path is a load error (1), not an argument error.
    let (code, lines) = validate(&[&dir.join("nope")]);
    assert_eq!(code, 1);
    assert!(
        lines[0].starts_with("error: ") && lines[0].contains("nope: cannot read"),
        "{lines:#?}"
    );
}

#[test]
fn wrong_arguments_exit_2() {
    let (code, _) = validate(&[]);
    assert_eq!(code, 2, "no path given");
    let status = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(["validate", "--no-such-flag", "x"])
        .status()
        .unwrap();
    assert_eq!(status.code(), Some(2));
}

#[test]
fn output_into_a_closed_pipe_ends_quietly_without_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    let sample = Path::new(env!("CARGO_MANIFEST_DIR")).join("sample-data");
    let mut child = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .arg("validate")
        .arg(&sample)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run pushlab");
    // Close the reading end before pushlab writes its first line, as `| head -0` does.
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("wait for pushlab");
    let stderr = String::from_utf8(out.stderr).expect("utf-8 stderr");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        out.status.signal(),
        Some(13),
        "ended by SIGPIPE: {:?}",
        out.status
    );
}
