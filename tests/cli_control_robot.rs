//! `pushlab control ws://…` against a robot that takes commands (the Foxglove SDK's server running
//! the sandbox's simulator, `sandbox_robot`): armed, it drives the box to the goal, prints a JSON
//! line per control step and a halt with the hold sent, records both ways, and exits 0; the
//! robot received exactly what it says it sent. Missing topics, a workspace without an area and
//! a pose filter that follows nothing are refused with the usage exit code.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::PathBuf;
use std::process::Command;

use pushlab_core::sandbox::{Mystery, MysteryObject};
use serde_json::Value;

use crate::sandbox_robot::{PLAIN, start};

fn setting(dir: &std::path::Path) -> PathBuf {
    let setting = Mystery::draw(4, MysteryObject::Box).unwrap().setting();
    let path = dir.join("setting.json");
    std::fs::write(&path, serde_json::to_string(&setting).unwrap()).unwrap();
    path
}

fn scratch(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("pushlab-cli-control-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn armed_it_drives_the_robot_to_the_goal_and_records_both_ways() {
    let robot = start(PLAIN);
    let dir = scratch("drive");
    let out = Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .args([
            "control", &robot.url, "--pusher", "/pusher", "--object", "/object",
        ])
        .args([
            "--command",
            "/pusher_target",
            "--goal",
            "0.07,0,0",
            "--arm",
            "--json",
        ])
        .args(["--time-limit", "60", "--setting"])
        .arg(setting(&dir))
        .arg("--record")
        .arg(dir.join("drive.mcap"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<Value> = stdout
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let said = lines[0]["said"].as_str().unwrap();
    assert!(
        said.contains("ARMED") && said.contains("/pusher_target (cdr)"),
        "{said}"
    );
    let steps = lines.iter().filter(|l| l.get("step").is_some()).count();
    assert!(steps > 20, "{steps} steps");
    let halted = lines.iter().find(|l| l.get("halted").is_some()).unwrap();
    assert_eq!(halted["halted"], "reached");
    assert_eq!(halted["hold"]["kind"], "hold");
    assert_eq!(halted["sent"], true);
    let outcome = &lines.last().unwrap()["outcome"];
    assert_eq!(outcome["why"], "reached");
    std::thread::sleep(std::time::Duration::from_millis(200));
    let received = robot.received[0].targets.lock().unwrap().len();
    assert_eq!(outcome["commands_sent"].as_u64(), Some(received as u64));
    assert!(std::fs::metadata(dir.join("drive.mcap")).unwrap().len() > 1000);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_robot_needs_its_topics_and_a_workspace_with_an_area() {
    let dir = scratch("usage");
    let run = |extra: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_pushlab"))
            .args([
                "control",
                "ws://127.0.0.1:9",
                "--pusher",
                "/p",
                "--object",
                "/o",
            ])
            .args(["--goal", "0.1,0,0", "--setting"])
            .arg(setting(&dir))
            .args(extra)
            .output()
            .unwrap()
    };
    let out = run(&[]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("driving a robot needs --command TOPIC"),
        "{err}"
    );
    let out = run(&["--command", "/t", "--workspace", "0,0,1,0"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--workspace '0,0,1,0'") && err.contains("has no area"),
        "{err}"
    );
    // A pose filter that would follow nothing is refused before anything connects.
    let out = run(&["--command", "/t", "--track", "0,0.1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--track") && err.contains("expected 0 < ALPHA ≤ 1 and 0 ≤ BETA < 1"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
