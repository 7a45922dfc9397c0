//! `pushlab suggest`: the ranked list a user reads, the errors a wrong object or push gets, and
//! `--measure-orders`, the ranking against the worst and random orders with the COM error after
//! each push.

use crate::skip;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn sample(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("sample-data")
        .join(name)
}

fn suggest(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pushlab"))
        .arg("suggest")
        .args(args)
        .output()
        .expect("runs pushlab")
}

/// The ranking's rows: the lines after its header.
fn ranked_rows(stdout: &str) -> Vec<&str> {
    stdout
        .lines()
        .skip_while(|l| !l.starts_with("rank"))
        .skip(1)
        .collect()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

#[test]
fn two_objects_ask_for_one_and_a_wrong_name_lists_them() {
    let front = sample("box1-paper-center-front");
    let left = sample("box1-paper-center-left");
    let output = suggest(&[front.as_os_str(), left.as_os_str()]);
    assert_eq!(output.status.code(), Some(2), "a usage error");
    assert!(
        text(&output.stderr).contains(
            "the recordings push 2 objects: choose one with --object, one of \
             'box1-paper-center-front' (36 pushes), 'box1-paper-center-left' (36 pushes)"
        ),
        "{}",
        text(&output.stderr)
    );
    let output = suggest(&[front.as_os_str(), "--object".as_ref(), "box9".as_ref()]);
    assert!(
        text(&output.stderr).contains("no object 'box9' in the recordings; there are"),
        "{}",
        text(&output.stderr)
    );
    let output = suggest(&[front.as_os_str(), "--after".as_ref(), "online_042".as_ref()]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr)
            .contains("--after online_042: no push of box1-paper-center-front is called that"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn the_ranking_lists_every_other_push_best_first_with_where_it_pushes() {
    let set = sample("box1-paper-center-left");
    let output = suggest(&[
        set.as_os_str(),
        "--object".as_ref(),
        "center-left".as_ref(),
        "--after".as_ref(),
        "online_000,online_004".as_ref(),
        "--optimizer".as_ref(),
        "gauss-newton".as_ref(),
        "--top".as_ref(),
        "5".as_ref(),
    ]);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        stdout.contains("after online_000, online_004: COM σ now"),
        "{stdout}"
    );
    let rows = ranked_rows(&stdout);
    assert_eq!(rows.len(), 5, "{stdout}");
    let sigma = |row: &str| -> f64 {
        let before_mm = row.split(" mm").next().expect("a σ");
        before_mm
            .split_whitespace()
            .last()
            .expect("a number")
            .parse()
            .expect("a number")
    };
    for pair in rows.windows(2) {
        assert!(sigma(pair[0]) <= sigma(pair[1]), "{stdout}");
    }
    for row in &rows {
        assert!(
            !row.contains("online_000 ") && !row.contains("online_004 "),
            "{row}"
        );
        assert!(row.contains(" cm ") && row.contains('°'), "{row}");
    }
}

#[test]
fn measuring_orders_reports_the_com_error_after_each_push_for_ranked_worst_and_random() {
    let set = sample("box1-paper-lr-front");
    let online: Vec<PathBuf> = (0..9)
        .map(|i| set.join(format!("online_{i:03}.csv")))
        .collect();
    let json = std::env::temp_dir().join(format!("pushlab-suggest-{}.json", std::process::id()));
    let mut args: Vec<&std::ffi::OsStr> = online.iter().map(|p| p.as_os_str()).collect();
    args.extend([
        "--optimizer".as_ref(),
        "gauss-newton".as_ref(),
        "--measure-orders".as_ref(),
        "4".as_ref(),
        "--json".as_ref(),
        json.as_os_str(),
    ]);
    let output = suggest(&args);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(stdout.contains("COM error after n pushes, mm"), "{stdout}");
    let report: Value = serde_json::from_slice(&std::fs::read(&json).expect("JSON")).expect("JSON");
    std::fs::remove_file(&json).ok();
    assert_eq!(report["random"].as_array().expect("orders").len(), 4);
    for order in ["ranked", "worst"] {
        let pushes = report[order].as_array().expect("an order");
        assert_eq!(pushes.len(), 9, "{order}");
        let mut seen: Vec<u64> = pushes
            .iter()
            .map(|p| p["push"].as_u64().expect("n"))
            .collect();
        seen.sort_unstable();
        assert_eq!(
            seen,
            (0..9).collect::<Vec<u64>>(),
            "{order}: each push once"
        );
        assert!(pushes.iter().all(|p| p["com_error_m"].as_f64().is_some()));
    }
    let summary = report["summary"].as_array().expect("rows");
    let after: Vec<u64> = summary
        .iter()
        .map(|r| r["after"].as_u64().expect("n"))
        .collect();
    assert_eq!(after, [1, 2, 3, 5, 9]);
    // After all nine pushes every order has learned the same pushes: the errors differ only by
    // the order, and the ranked order's is among the random ones' range or near it.
    let last = &summary[4];
    let f = |k: &str| last[k].as_f64().expect(k);
    assert!(f("random_p10_m") <= f("random_median_m") && f("random_median_m") <= f("random_p90_m"));
    let table_row = stdout
        .lines()
        .find(|l| l.trim_start().starts_with("9 "))
        .expect("a row for 9");
    assert!(
        table_row.contains(&format!("{:.1}", f("ranked_m") * 1e3)),
        "{table_row}"
    );
}

#[test]
fn measuring_orders_without_a_true_com_says_so() {
    // The MIT dataset gives the hexagon no COM.
    let Some(mit) = skip::shared(Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push") else {
        return;
    };
    let output = suggest(&[
        mit.as_os_str(),
        "--object".as_ref(),
        "abs-hex".as_ref(),
        "--measure-orders".as_ref(),
        "2".as_ref(),
    ]);
    assert_eq!(output.status.code(), Some(2));
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains(
            "--measure-orders needs the true COM to measure against, and the recordings of \
             mit-abs-hex do not give it"
        ),
        "{stderr}"
    );
}

#[test]
fn a_grid_of_pushes_is_ranked_instead_of_the_recordings() {
    let set = sample("box1-paper-center-front");
    let output = suggest(&[
        set.as_os_str(),
        "--after".as_ref(),
        "online_000".as_ref(),
        "--grid".as_ref(),
        "--grid-offsets".as_ref(),
        "0".as_ref(),
        "--grid-angles".as_ref(),
        "0".as_ref(),
    ]);
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stderr}");
    assert!(
        stdout.contains("a grid of 4 pushes, 10 cm each at 4.0 cm/s, 10 Hz"),
        "{stdout}"
    );
    let rows = ranked_rows(&stdout);
    assert_eq!(rows.len(), 4, "{stdout}");
    for side in [
        "front +0.0 cm +0°",
        "left +0.0 cm +0°",
        "back +0.0 cm +0°",
        "right +0.0 cm +0°",
    ] {
        assert!(rows.iter().any(|r| r.contains(side)), "{side}: {stdout}");
    }
    let output = suggest(&[
        set.as_os_str(),
        "--grid".as_ref(),
        "--grid-offsets".as_ref(),
        "-1".as_ref(),
    ]);
    assert_eq!(output.status.code(), Some(2));
    assert!(
        text(&output.stderr).contains("--grid-offsets -1: an offset is a fraction of the face's"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn the_columns_line_up_under_their_header_with_mit_files_long_names() {
    let Some(folder) = skip::shared(Path::new(env!("CARGO_MANIFEST_DIR")), "mit-push-abs-train")
    else {
        return;
    };
    let entries = std::fs::read_dir(&folder).expect("the folder lists");
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.to_string_lossy().contains("shape=ellip1_"))
        .collect();
    files.sort();
    files.truncate(4);
    let args: Vec<&std::ffi::OsStr> = files.iter().map(|p| p.as_os_str()).collect();
    let output = suggest(&args);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let header = stdout
        .lines()
        .find(|l| l.starts_with("rank"))
        .expect("a header");
    // Where each word ends, counted in characters (the header's σ is two bytes).
    let ends = |line: &str| -> Vec<usize> {
        let chars: Vec<char> = line.chars().collect();
        (0..chars.len())
            .filter(|&i| chars[i] != ' ' && chars.get(i + 1).is_none_or(|c| *c == ' '))
            .map(|i| i + 1)
            .collect()
    };
    let header_ends = ends(header);
    let rows = ranked_rows(&stdout);
    assert_eq!(rows.len(), files.len(), "{stdout}");
    for row in rows {
        assert!(row.contains("motion_surface=abs_shape=ellip1_"), "{row}");
        let row_ends = ends(row);
        // The rank and the face (an ellipse's faces are numbered) end where their headers do,
        // after names of 60 characters; the row ends under "shrinks".
        assert_eq!(row_ends[0], header_ends[0], "{stdout}");
        assert_eq!(row_ends[2], header_ends[2], "{stdout}");
        assert_eq!(row_ends.last(), header_ends.last(), "{stdout}");
    }
}
