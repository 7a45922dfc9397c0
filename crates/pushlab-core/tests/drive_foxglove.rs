//! The controller driving a robot through a real peer: the Foxglove SDK's WebSocket server, with
//! client publish, running the sandbox's simulator as the robot (its pusher follows the targets
//! it is sent at the robot's own speed; the object moves as the simulator pushes it). The session
//! reaches the goal; what was sent and received is in the MCAP; and each of the safety rules is
//! seen from the robot's side: nothing before arming, one hold on stale poses, on Ctrl-C and on a
//! lost link, and a server without client publish refused by name.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use nalgebra::Point2;
use pushlab_core::control::drive::{Command, Drive, DriveConfig, DriveEvent, Halt};
use pushlab_core::control::{Goal, Pacing, PlanWith, PlannerConfig, PoseControl};
use pushlab_core::geometry::Pose2;
use pushlab_core::learn::OnlineConfig;
use pushlab_core::model_file::ModelFile;
use pushlab_core::sandbox::{Mystery, MysteryObject};

use crate::sandbox_robot::{PLAIN, Robot, start};

const GOAL: Pose2 = Pose2 {
    position: Point2::new(0.07, 0.0),
    yaw: 0.0,
};

fn control(plan_with: PlanWith) -> PoseControl {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/default-model.json");
    let model = ModelFile::load(&path).unwrap().combined;
    let setting = Mystery::draw(4, MysteryObject::Box).unwrap().setting();
    PoseControl::new(
        &model,
        &setting,
        plan_with,
        OnlineConfig::default(),
        Goal::at(GOAL),
        PlannerConfig::default(),
        Pacing::sandbox(),
    )
    .unwrap()
}

fn config(url: &str, arm: bool, time_limit_s: f64, record: Option<&Path>) -> DriveConfig {
    DriveConfig {
        url: url.to_owned(),
        pusher_topic: "/pusher".into(),
        object_topic: "/object".into(),
        command_topic: "/pusher_target".into(),
        frame_id: "table".into(),
        record: record.map(Path::to_path_buf),
        workspace: None,
        pacing: Pacing::sandbox(),
        arm,
        time_limit_s,
    }
}

/// Drives until the end, `stop` asked as the user's interrupt; every event kept.
fn drive(
    config: DriveConfig,
    plan_with: PlanWith,
    stop: &dyn Fn() -> bool,
) -> (pushlab_core::control::drive::DriveEnd, Vec<DriveEvent>) {
    let (drive, _) = Drive::open(config, control(plan_with), &|| false).expect("opens");
    let mut events = Vec::new();
    let end = drive
        .run(stop, &mut || None, &mut |e| events.push(e))
        .expect("runs");
    (end, events)
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("pushlab-drive-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn a_robot_driven_through_its_foxglove_server_reaches_the_goal_and_the_mcap_holds_both_ways() {
    let robot = start(PLAIN);
    let dir = scratch("reach");
    let file = dir.join("drive.mcap");
    let (end, events) = drive(
        config(&robot.url, true, 60.0, Some(&file)),
        PlanWith::Online,
        &|| false,
    );
    assert_eq!(end.why, Halt::Reached, "{events:?}");
    assert!(
        matches!(
            events.last(),
            Some(DriveEvent::Halted {
                why: Halt::Reached,
                hold: Some(Command::Hold { .. }),
                sent: true
            })
        ),
        "the goal reached, one hold sent: {:?}",
        events.last()
    );
    std::thread::sleep(Duration::from_millis(200));
    let targets = robot.received[0].targets.lock().unwrap().clone();
    assert_eq!(robot.received[0].advertised.load(Ordering::SeqCst), 1);
    assert_eq!(targets.len() as u64, end.commands_sent);
    assert!(targets.len() > 20, "{} targets", targets.len());
    // The last is the hold: the pusher's position, where the robot had it.
    let last = targets.last().unwrap().1;
    let pusher = robot.pusher.lock().unwrap().0;
    assert!(
        (last - pusher).norm() < 0.005,
        "hold at {last:?}, pusher at {pusher:?}"
    );
    // Every step the gate let out is within a step of the pusher at 4 cm/s and 10 Hz.
    for e in &events {
        if let DriveEvent::Step {
            step,
            command: Some(c),
            ..
        } = e
        {
            let from = Point2::new(step.pusher[0], step.pusher[1]);
            assert!((c.point() - from).norm() <= 0.004 + 1e-9, "{e:?}");
        }
    }

    // The recording: every command sent, and the poses received, each on its topic.
    let bytes = std::fs::read(&file).unwrap();
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for message in mcap::MessageStream::new(&bytes).unwrap() {
        let message = message.unwrap();
        *counts.entry(message.channel.topic.clone()).or_default() += 1;
    }
    assert_eq!(
        counts.get("/pusher_target").copied(),
        Some(targets.len()),
        "{counts:?}"
    );
    let poses =
        counts.get("/pusher").copied().unwrap_or(0) + counts.get("/object").copied().unwrap_or(0);
    let published = robot.published.load(Ordering::SeqCst);
    assert!(
        poses <= published && poses + 20 >= published,
        "{poses} recorded of {published} published"
    );
    drop(robot);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn nothing_reaches_the_robot_until_it_is_armed() {
    let robot = start(PLAIN);
    let (end, events) = drive(
        config(&robot.url, false, 1.5, None),
        PlanWith::Online,
        &|| false,
    );
    assert_eq!(end.why, Halt::TimeLimit);
    let planned = events
        .iter()
        .filter(|e| matches!(e, DriveEvent::Step { .. }))
        .count();
    assert!(planned >= 8, "{planned} steps planned");
    assert_eq!(robot.received[0].advertised.load(Ordering::SeqCst), 1);
    assert!(robot.received[0].targets.lock().unwrap().is_empty());
    assert_eq!(end.commands_sent, 0);
}

#[test]
fn a_server_without_client_publish_is_refused_by_name() {
    let robot = start(Robot {
        client_publish: false,
        ..PLAIN
    });
    let Err(why) = Drive::open(
        config(&robot.url, true, 5.0, None),
        control(PlanWith::Online),
        &|| false,
    ) else {
        panic!("drove a robot whose server takes no client messages");
    };
    let why = why.to_string();
    assert!(
        why.contains(&robot.url) && why.contains("does not offer client publish"),
        "{why}"
    );
}

#[test]
fn stale_poses_send_one_hold_and_nothing_after() {
    let robot = start(Robot {
        poses_for: Some(Duration::from_millis(1500)),
        ..PLAIN
    });
    let (end, _) = drive(
        config(&robot.url, true, 10.0, None),
        PlanWith::Online,
        &|| false,
    );
    assert_eq!(end.why, Halt::Stale);
    std::thread::sleep(Duration::from_millis(500));
    let targets = robot.received[0].targets.lock().unwrap().clone();
    assert!(
        targets.len() >= 5,
        "{} targets before the poses stopped",
        targets.len()
    );
    // The hold: where the pusher was last seen, sent once the newest pose was 200 ms old (at
    // the first control step after that), and nothing after it.
    let (held_at, hold) = *targets.last().unwrap();
    let (pusher, last_pose) = *robot.pusher.lock().unwrap();
    assert!(
        (hold - pusher).norm() < 1e-9,
        "hold at {hold:?}, pusher last at {pusher:?}"
    );
    let late = held_at - last_pose;
    assert!(
        late >= Duration::from_millis(200) && late <= Duration::from_millis(400),
        "the hold {late:?} after the last pose"
    );
}

#[test]
fn ctrl_c_sends_one_hold() {
    let robot = start(PLAIN);
    let started = Instant::now();
    let (end, _) = drive(
        config(&robot.url, true, 30.0, None),
        PlanWith::Online,
        &|| started.elapsed() > Duration::from_millis(1500),
    );
    assert_eq!(end.why, Halt::Interrupted);
    std::thread::sleep(Duration::from_millis(300));
    let targets = robot.received[0].targets.lock().unwrap().clone();
    let hold = targets.last().unwrap().1;
    let pusher = robot.pusher.lock().unwrap().0;
    assert!(
        (hold - pusher).norm() < 0.005,
        "hold at {hold:?}, pusher at {pusher:?}"
    );
    assert_eq!(targets.len() as u64, end.commands_sent);
}

#[test]
fn a_lost_link_sends_one_hold_when_it_is_back_and_nothing_more() {
    let robot = start(Robot {
        restart_after: Some(Duration::from_millis(1500)),
        ..PLAIN
    });
    let (end, events) = drive(
        config(&robot.url, true, 30.0, None),
        PlanWith::Online,
        &|| false,
    );
    assert_eq!(end.why, Halt::LinkLost, "{events:?}");
    std::thread::sleep(Duration::from_millis(500));
    assert!(!robot.received[0].targets.lock().unwrap().is_empty());
    // The server back: the command topic advertised again, and one message on it: the hold.
    let after = robot.received[1].targets.lock().unwrap().clone();
    assert_eq!(robot.received[1].advertised.load(Ordering::SeqCst), 1);
    assert_eq!(after.len(), 1, "{after:?}");
    assert!(matches!(
        events.last(),
        Some(DriveEvent::Halted {
            why: Halt::LinkLost,
            sent: true,
            ..
        })
    ));
}
