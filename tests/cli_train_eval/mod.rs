//! `pushlab train` and `pushlab eval` end to end: the built binary on a small subset of the sample
//! data with few epochs; the JSON report's fields and values, the figure, exit codes 1 and 2 with their
//! messages, labels (splits, bad tracking, per-label means) and a train → eval --model round trip.
//! One test binary: `report` (eval's JSON, figure and best fits), `round_trip` (train, then eval with
//! the model; Ctrl-C), `inputs` (what is used and refused: exit codes, labels, the real MIT files).
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

use crate::cli_common;
mod figure;
mod inputs;
mod report;
mod round_trip;

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
