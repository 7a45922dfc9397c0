//! `pushlab live` against a real peer: the Foxglove SDK's WebSocket server, in this test process,
//! logging a pusher (JSON) and an object (CDR PoseStamped) every 10 ms. The command must print a
//! line a second with the latest poses, write every message to `--record`, and the recording must
//! open with `pushlab validate` as a bag with both topics; a topic that is not advertised, or an
//! existing file to record to, is an error naming it.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::cli_common;
use crate::live_robot;

use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::Duration;

use cli_common::{pushlab, temp_dir};
use live_robot::{pushing_robot, restarting_robot, robot};

#[test]
fn live_prints_the_poses_and_records_every_message_to_a_bag() {
    let (url, stop, logging) = robot();
    let dir = temp_dir("pushlab-live", "record");
    let out = dir.join("session.mcap");
    let out_s = out.display().to_string();
    let run = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--record",
        &out_s,
        "--duration",
        "2.5",
        "--json",
    ]);
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains(&format!(
            "connected to {url} (test robot, foxglove.sdk.v1): 2 channel(s), recording to {out_s}"
        )),
        "{}",
        run.stdout
    );
    let lines: Vec<serde_json::Value> = (run.stdout.lines())
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert!(
        lines.len() >= 3,
        "a line a second and one at the end: {}",
        run.stdout
    );
    let last = lines.last().unwrap();
    assert_eq!(last["pusher"]["x"], 0.25);
    assert_eq!(last["object"]["y"], 0.5);
    let messages = last["messages"].as_u64().unwrap();
    assert!(messages > 100, "{messages} messages in 2.5 s at 2 × 100/s");
    assert!(
        run.stdout.contains(&format!(
            "recorded {messages} message(s) on 2 channel(s) to {out_s}"
        )),
        "{}",
        run.stdout
    );

    // The recording is a bag: both topics, every message.
    let validate = pushlab(&["validate", &out_s]);
    assert_eq!(validate.code, 0, "{}\n{}", validate.stdout, validate.stderr);
    assert!(
        validate
            .stdout
            .contains("/object geometry_msgs/msg/PoseStamped, "),
        "{}",
        validate.stdout
    );
    let counts: u64 = (validate.stdout.lines())
        .filter_map(|l| {
            l.split(", ")
                .nth(1)?
                .strip_suffix(" messages")?
                .parse::<u64>()
                .ok()
        })
        .sum();
    assert_eq!(counts, messages, "{}", validate.stdout);

    // The recording imports as any bag, the JSON pusher read as the live session read it.
    let setting = dir.join("box.json");
    std::fs::write(
        &setting,
        r#"{"name": "live-box", "object": {"shape": "box", "width": 0.1, "length": 0.12},
            "pusher_radius": 0.005, "trajectories": []}"#,
    )
    .unwrap();
    let set = dir.join("set");
    let import = pushlab(&[
        "import",
        &out_s,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--setting",
        setting.to_str().unwrap(),
        "--out",
        set.to_str().unwrap(),
    ]);
    assert_eq!(import.code, 0, "{}\n{}", import.stdout, import.stderr);
    let csv = std::fs::read_dir(&set)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "csv"))
        .expect("a push written");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time,robot_x,robot_y,object_x,object_y,object_theta")
    );
    let first: Vec<f64> = (lines.next().unwrap().split(','))
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(first[1..], [0.25, -0.5, 0.125, 0.5, 0.0], "{text:.200}");

    // Never over an existing file; a topic that is not advertised is named with those that are.
    let again = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--record",
        &out_s,
        "--duration",
        "1",
    ]);
    assert_eq!(again.code, 1);
    assert!(again.stderr.contains("already exists"), "{}", again.stderr);
    let missing = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/box",
        "--duration",
        "1",
    ]);
    assert_eq!(missing.code, 1);
    assert!(
        missing
            .stderr
            .contains("no topic /box advertised within 5 s; the server's topics: ")
            && missing
                .stderr
                .contains("/object (geometry_msgs/msg/PoseStamped)"),
        "{}",
        missing.stderr
    );
    stop.store(true, Ordering::Relaxed);
    logging.join().unwrap();
}

#[test]
fn live_learns_theta_as_the_push_arrives_and_eval_of_its_recording_agrees_to_the_bit() {
    let (url, stop, logging) = pushing_robot(Duration::from_millis(2));
    let dir = temp_dir("pushlab-live", "learn");
    let out = dir.join("push.mcap");
    let out_s = out.display().to_string();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let setting = root.join("sample-data/box1-paper-ur-front/setting.json");
    let setting_s = setting.display().to_string();
    let run = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--setting",
        &setting_s,
        "--record",
        &out_s,
        "--duration",
        "2.5",
        "--json",
    ]);
    stop.store(true, Ordering::Relaxed);
    logging.join().unwrap();
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stdout.contains(
            "learning θ online with the default model (assets/default-model.json) (horizon 10 frames) on a 10 Hz grid"
        ),
        "{}",
        run.stdout
    );
    let last: serde_json::Value = (run.stdout.lines())
        .rfind(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .unwrap();
    let learning = &last["learning"];
    let frontier = learning["frontier"].as_u64().unwrap() as usize;
    assert!(frontier > 80, "the 10 s push learned: {learning}");
    assert_eq!(
        learning["mean_losses"]["frames"].as_u64(),
        Some(frontier as u64)
    );
    // The prediction a horizon ahead of the newest frame, scored as the frames came.
    let ahead = &learning["ahead"];
    assert_eq!(
        ahead["frame"].as_u64(),
        Some(learning["frames"].as_u64().unwrap() - 1 + 10),
        "{learning}"
    );
    let off = ahead["mean_position_m"].as_f64().unwrap();
    assert!(
        ahead["scored"].as_u64().unwrap() > 70 && off > 0.0 && off < 0.03,
        "{ahead}"
    );
    eprintln!("ahead 1 s: {ahead}");
    let sigma = learning["sigma"]["com_offset"][0].as_f64().unwrap();
    assert!(sigma > 0.0 && sigma < 0.05, "{learning}");

    // The recording, imported at the grid's rate and evaluated with the same model.
    let set = dir.join("set");
    let import = pushlab(&[
        "import",
        &out_s,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--setting",
        &setting_s,
        "--rate",
        "10",
        "--out",
        set.to_str().unwrap(),
    ]);
    assert_eq!(import.code, 0, "{}\n{}", import.stdout, import.stderr);
    let report = dir.join("eval.json");
    let model = root.join("assets/default-model.json");
    let eval = pushlab(&[
        "eval",
        "--model",
        model.to_str().unwrap(),
        "--online",
        set.to_str().unwrap(),
        "--per-frame",
        "--json",
        report.to_str().unwrap(),
    ]);
    assert_eq!(eval.code, 0, "{}\n{}", eval.stdout, eval.stderr);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let push = &report["trajectories"][0];
    let frames = push["frames"].as_array().unwrap();
    assert!(frontier <= frames.len(), "{frontier} of {}", frames.len());
    // θ where the session stopped learning: a frame of the report, or the push's end.
    let (theta_com, theta_h) = match frames.get(frontier) {
        Some(f) => (f["theta"]["com_offset"].clone(), f["theta"]["h"].clone()),
        None => (
            push["com_offset_learned"].clone(),
            push["h_learned"].clone(),
        ),
    };
    assert_eq!(learning["theta"]["com_offset"], theta_com, "{learning}");
    assert_eq!(learning["theta"]["h"], theta_h);
    let online_pos: f64 = frames[..frontier]
        .iter()
        .map(|f| f["online"]["pos"].as_f64().unwrap())
        .sum::<f64>()
        / frontier as f64;
    assert_eq!(
        learning["mean_losses"]["online_pos"]
            .as_f64()
            .unwrap()
            .to_bits(),
        online_pos.to_bits()
    );
    assert_ne!(
        theta_com, report["config"]["theta0"]["com_offset"],
        "θ was learned"
    );
}

#[test]
fn live_connects_again_when_the_server_comes_back_and_follows_the_topics_by_name() {
    let (url, stop, logging) = restarting_robot();
    let dir = temp_dir("pushlab-live", "restart");
    let out = dir.join("session.mcap");
    let out_s = out.display().to_string();
    let run = pushlab(&[
        "live",
        &url,
        "--pusher",
        "/pusher",
        "--object",
        "/object",
        "--record",
        &out_s,
        "--duration",
        "4",
        "--json",
    ]);
    stop.store(true, Ordering::Relaxed);
    logging.join().unwrap();
    assert_eq!(run.code, 0, "{}\n{}", run.stdout, run.stderr);
    assert!(
        run.stderr.contains("the connection ended")
            && run
                .stderr
                .contains("connecting again (Ctrl-C ends the session)"),
        "{}",
        run.stderr
    );
    let reconnected = (run.stdout.lines())
        .position(|l| l.starts_with(&format!("reconnected to {url} after ")))
        .unwrap_or_else(|| panic!("{}", run.stdout));
    assert!(reconnected > 0, "{}", run.stdout);
    let after = (run.stdout.lines())
        .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
        .filter_map(|v| v["messages"].as_u64())
        .max()
        .unwrap_or(0);
    // The first server logs for 1 s at 2 × 100 messages/s: more came from the second.
    assert!(after > 300, "{after} messages\n{}", run.stdout);

    // One channel per topic in the file, though the server numbered them anew.
    let validate = pushlab(&["validate", &out_s]);
    assert_eq!(validate.code, 0, "{}\n{}", validate.stdout, validate.stderr);
    let topics: Vec<&str> = (validate.stdout.lines())
        .filter(|l| l.contains(" messages"))
        .collect();
    assert_eq!(topics.len(), 2, "{}", validate.stdout);
    let recorded: u64 = topics
        .iter()
        .filter_map(|l| {
            l.split(", ")
                .nth(1)?
                .strip_suffix(" messages")?
                .parse::<u64>()
                .ok()
        })
        .sum();
    assert_eq!(recorded, after, "{}", validate.stdout);
}
