//! What the CLI's test files share: running the built binary and a fresh temporary folder.

#![allow(dead_code, clippy::expect_used)] // each test file uses its own part

use std::path::PathBuf;
use std::process::Command;

/// What a run of `pushlab` gave back.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

/// Runs the built `pushlab` binary with `args` and waits for it.
pub fn pushlab(args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args(args)
        .output()
        .expect("run pushlab");
    Run {
        code: out.status.code().expect("exit code"),
        stdout: String::from_utf8(out.stdout).expect("utf-8 stdout"),
        stderr: String::from_utf8(out.stderr).expect("utf-8 stderr"),
    }
}

/// An empty folder under cargo's temporary folder for integration tests (inside `target/`, so a
/// test run leaves nothing in the system's), unique to this test process and `name`.
pub fn temp_dir(prefix: &str, name: &str) -> PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(format!("{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create a temporary folder");
    dir
}
