//! Drive, in the app's Connect dialog, against a robot that takes commands (`sandbox_robot`: the
//! Foxglove SDK's server with client publish, running the sandbox's simulator). The app plans on
//! its own run of the live push and its worker sends through the core's commander: nothing before
//! Arm, the goal reached with one hold, and every message both ways in the MCAP. A window that
//! stops planning, Pause and Disconnect each send one hold and nothing after; a server without
//! client publish is refused by name and the session watches on. The goal dragged in the scene
//! moves it and pauses an armed drive; one off the workspace is refused.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use eframe::egui;
use nalgebra::Point2;
use pushlab::app::initial_state;
use pushlab::app::state::sources::live::{
    DriveChoice, DriveCommand, DriveStatus, Link, LiveChoice, LiveCommand,
};
use pushlab::app::state::{AppState, Command, Persisted};
use pushlab_core::control::drive::{Command as Sent, Halt};
use pushlab_core::sandbox::{Mystery, MysteryObject};

use crate::common;
use crate::sandbox_robot::{PLAIN, Robot, Running, start};

/// Advances the state as the app's frames would (60 a second) until `done` or `limit`.
fn advance_until(
    state: &mut AppState,
    what: &str,
    limit: Duration,
    done: impl Fn(&AppState) -> bool,
) {
    let started = Instant::now();
    while !done(state) {
        assert!(
            started.elapsed() < limit,
            "{what}: status {:?}, drive {:?}",
            state.status(),
            drive(state)
        );
        state.advance(1.0 / 60.0);
        std::thread::sleep(Duration::from_millis(16));
    }
}

/// Advances the state for `time` whatever happens.
fn advance_for(state: &mut AppState, time: Duration) {
    let started = Instant::now();
    while started.elapsed() < time {
        state.advance(1.0 / 60.0);
        std::thread::sleep(Duration::from_millis(16));
    }
}

fn drive(state: &AppState) -> DriveStatus {
    (state.live().running())
        .and_then(|r| r.latest.drive.clone())
        .unwrap_or_default()
}

fn targets(robot: &Running) -> Vec<Point2<f64>> {
    let received = robot.received[0].targets.lock().unwrap();
    received.iter().map(|(_, p)| *p).collect()
}

/// The app connected to `robot` with Drive on, the goal 7 cm ahead of the box, recording to
/// `record`; the live push growing.
fn connected(robot: &Running, dir: &Path, record: Option<PathBuf>) -> AppState {
    let setting = Mystery::draw(4, MysteryObject::Box).unwrap().setting();
    let setting_path = dir.join("setting.json");
    std::fs::write(&setting_path, serde_json::to_string(&setting).unwrap()).unwrap();
    let mut state = initial_state(&[], Persisted::default());
    state.apply(Command::Live(LiveCommand::OpenForm));
    state.apply(Command::Live(LiveCommand::Edit(LiveChoice {
        url: robot.url.clone(),
        pusher: "/pusher".into(),
        object: "/object".into(),
        setting: setting_path,
        record: record.unwrap_or_default(),
        rate_hz: None,
        drive: Box::new(DriveChoice {
            on: true,
            frame: "table".into(),
            goal: [0.07, 0.0, 0.0],
            ..DriveChoice::default()
        }),
    })));
    state.apply(Command::Live(LiveCommand::Connect));
    assert!(
        state.live().form().is_none(),
        "connected: {:?}",
        state.live().form().and_then(|f| f.error.clone())
    );
    advance_until(&mut state, "frames arrive", Duration::from_secs(20), |s| {
        s.recording().map_or(0, |r| r.trajectory.len()) >= 10
    });
    state
}

/// Disconnect, and the session's end.
fn disconnect(state: &mut AppState) {
    state.apply(Command::Live(LiveCommand::Disconnect));
    advance_until(state, "the session ends", Duration::from_secs(10), |s| {
        matches!(
            s.live().running().map(|r| &r.latest.link),
            Some(Link::Ended { .. })
        )
    });
}

fn is_hold_at_pusher(robot: &Running, sent: Point2<f64>) -> bool {
    let pusher = robot.pusher.lock().unwrap().0;
    (sent - pusher).norm() < 0.005
}

#[test]
fn armed_from_the_dialog_the_app_drives_the_robot_to_the_goal_and_records_both_ways() {
    let robot = start(PLAIN);
    let dir = common::scratch_dir("app-live-drive");
    let record = dir.join("drive.mcap");
    let mut state = connected(&robot, &dir, Some(record.clone()));

    // Planning, not sending: the command topic is advertised, nothing reaches the robot.
    advance_for(&mut state, Duration::from_millis(500));
    assert_eq!(robot.received[0].advertised.load(Ordering::SeqCst), 1);
    assert!(targets(&robot).is_empty(), "{:?}", targets(&robot));
    let status = drive(&state);
    assert!(!status.armed && status.sent == 0, "{status:?}");
    let run = state.run().expect("the live push is learned");
    assert!(run.frontier() > 0);

    state.apply(Command::Live(LiveCommand::Drive(DriveCommand::Arm)));
    advance_until(
        &mut state,
        "the goal reached",
        Duration::from_secs(90),
        |s| drive(s).halted == Some(Halt::Reached),
    );
    let status = state.status().unwrap_or_default().to_owned();
    assert!(status.contains("the goal is reached and held"), "{status}");
    // Its time is counted from Arm, not from Connect: the half second watched before is not in it.
    let time_s: f64 = (status.split(" in ").nth(1))
        .and_then(|rest| rest.split(" s from Arm").next())
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("{status}"));
    let frames = state.recording().unwrap().trajectory.len() as f64;
    assert!(
        time_s > 1.0 && time_s < frames / 10.0 - 0.4,
        "{time_s} s from Arm, of {frames} frames at 10 Hz"
    );
    advance_for(&mut state, Duration::from_millis(400));
    let sent = targets(&robot);
    let status = drive(&state);
    assert_eq!(sent.len() as u64, status.sent, "{status:?}");
    assert!(sent.len() > 20, "{} targets", sent.len());
    assert!(
        matches!(status.last, Some(Sent::Hold { .. })),
        "the last sent is the hold: {status:?}"
    );
    assert!(is_hold_at_pusher(&robot, *sent.last().unwrap()));
    // The object is at the goal (10 mm, 3°), as the robot's simulator has it.
    let object = state
        .recording()
        .unwrap()
        .trajectory
        .frames
        .last()
        .unwrap()
        .object;
    assert!(
        (object.position - Point2::new(0.07, 0.0)).norm() < 0.012,
        "{object:?}"
    );
    // Every target is within a step at 4 cm/s and 10 Hz of the pusher the robot had.
    let step = 0.04 / 10.0;
    for pair in sent.windows(2) {
        assert!((pair[1] - pair[0]).norm() <= 2.0 * step + 1e-9, "{pair:?}");
    }

    disconnect(&mut state);
    assert_eq!(
        targets(&robot).len(),
        sent.len(),
        "nothing after the goal's hold"
    );
    // The recording, as pushlab lists a bag: every target sent, and the poses received.
    let listing = pushlab_core::recording::bag::topics(&record).unwrap();
    let counts: std::collections::BTreeMap<String, u64> = (listing.topics.iter())
        .map(|t| (t.topic.clone(), t.count))
        .collect();
    assert_eq!(
        counts.get("/pusher_target"),
        Some(&(sent.len() as u64)),
        "{counts:?}"
    );
    assert!(counts.get("/pusher").is_some_and(|n| *n > 50), "{counts:?}");
    assert!(counts.get("/object").is_some_and(|n| *n > 50), "{counts:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_frozen_window_pause_and_disconnect_each_hold_the_pusher_once() {
    let robot = start(PLAIN);
    let dir = common::scratch_dir("app-live-drive-holds");
    let mut state = connected(&robot, &dir, None);
    let armed_and_sending = |state: &mut AppState, robot: &Running| {
        state.apply(Command::Live(LiveCommand::Drive(DriveCommand::Arm)));
        let before = targets(robot).len();
        advance_until(state, "targets sent", Duration::from_secs(20), |_| {
            targets(robot).len() >= before + 5
        });
    };

    // The window stops planning (no frame drawn for half a second): the worker holds the pusher
    // once the plan is 200 ms old, and sends nothing after.
    armed_and_sending(&mut state, &robot);
    std::thread::sleep(Duration::from_millis(500));
    let sent = targets(&robot);
    state.advance(1.0 / 60.0);
    assert_eq!(
        drive(&state).halted,
        Some(Halt::PlanStale),
        "{:?}",
        drive(&state)
    );
    assert!(matches!(drive(&state).last, Some(Sent::Hold { .. })));
    assert!(is_hold_at_pusher(&robot, *sent.last().unwrap()));
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(targets(&robot).len(), sent.len(), "nothing after the hold");

    // Pause: one hold, nothing after though the window plans on.
    armed_and_sending(&mut state, &robot);
    state.apply(Command::Live(LiveCommand::Drive(DriveCommand::Pause)));
    advance_for(&mut state, Duration::from_millis(300));
    let sent = targets(&robot);
    assert_eq!(drive(&state).halted, Some(Halt::Paused));
    assert!(is_hold_at_pusher(&robot, *sent.last().unwrap()));
    advance_for(&mut state, Duration::from_millis(400));
    assert_eq!(
        targets(&robot).len(),
        sent.len(),
        "nothing after the pause's hold"
    );

    // Disconnect while armed: one hold as the session ends.
    armed_and_sending(&mut state, &robot);
    disconnect(&mut state);
    std::thread::sleep(Duration::from_millis(200));
    let sent = targets(&robot);
    assert!(matches!(drive(&state).last, Some(Sent::Hold { .. })));
    assert!(is_hold_at_pusher(&robot, *sent.last().unwrap()));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_server_without_client_publish_is_refused_by_name_and_the_session_watches_on() {
    let robot = start(Robot {
        client_publish: false,
        ..PLAIN
    });
    let dir = common::scratch_dir("app-live-drive-refused");
    let mut state = connected(&robot, &dir, None);
    let refused = drive(&state).refused.expect("refused");
    assert!(refused.contains("client publish"), "{refused}");
    assert!(
        state.live().running().unwrap().drive.is_none(),
        "nothing is planned for a server that cannot be driven"
    );
    let frames = state.recording().unwrap().trajectory.len();
    advance_for(&mut state, Duration::from_millis(500));
    assert!(
        state.recording().unwrap().trajectory.len() > frames,
        "watching on"
    );
    state.apply(Command::Live(LiveCommand::Drive(DriveCommand::Arm)));
    advance_for(&mut state, Duration::from_millis(500));
    assert!(targets(&robot).is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The strip as a user sees it: NOT ARMED and its Arm button, then ARMED with Pause, then HELD
/// after Pause, each button clicked in the window.
#[test]
fn the_strips_buttons_arm_and_pause_the_drive_in_the_window() {
    use egui_kittest::kittest::Queryable;

    let robot = start(PLAIN);
    let dir = common::scratch_dir("app-live-drive-strip");
    let state = connected(&robot, &dir, None);
    let mut harness = common::harness(pushlab::app::PushlabApp::new(state), 1.0 / 60.0);
    let run_for = |harness: &mut egui_kittest::Harness<'_, pushlab::app::PushlabApp>, ms| {
        let started = Instant::now();
        while started.elapsed() < Duration::from_millis(ms) {
            harness.run_steps(1);
            std::thread::sleep(Duration::from_millis(16));
        }
    };
    run_for(&mut harness, 300);
    harness.get_by_label("NOT ARMED");
    assert!(targets(&robot).is_empty());
    harness.get_by_label("Arm").click();
    run_for(&mut harness, 600);
    harness.get_by_label("ARMED");
    assert!(
        !targets(&robot).is_empty(),
        "armed from the window: targets sent"
    );
    harness.get_by_label("Pause").click();
    run_for(&mut harness, 400);
    harness.get_by_label("HELD");
    assert_eq!(drive(&harness.state().state).halted, Some(Halt::Paused));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Presses at `from`, drags to `to` in steps, and lets go, as a hand on the scene does.
fn drag(
    harness: &mut egui_kittest::Harness<'_, pushlab::app::PushlabApp>,
    from: egui::Pos2,
    to: egui::Pos2,
) {
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::default(),
    };
    harness.event(egui::Event::PointerMoved(from));
    harness.run_steps(1);
    harness.event(button(from, true));
    harness.run_steps(1);
    for i in 1..=10 {
        harness.event(egui::Event::PointerMoved(
            from + (to - from) * (i as f32 / 10.0),
        ));
        harness.run_steps(1);
    }
    harness.event(button(to, false));
    harness.run_steps(1);
}

/// The goal's ghost dragged in the scene: the planner heads for where it was let go, the form's
/// choice remembers it, and the armed drive pauses with one hold (re-aiming a pushing robot is
/// the user's to confirm with Arm). A goal where the box would leave the workspace is refused
/// and said, the goal left where it was.
#[test]
fn dragging_the_goals_ghost_moves_the_drives_goal_and_pauses_an_armed_drive() {
    let robot = start(PLAIN);
    let dir = common::scratch_dir("app-live-drive-goal");
    let mut state = connected(&robot, &dir, None);
    state.apply(Command::Live(LiveCommand::Drive(DriveCommand::Arm)));
    advance_until(&mut state, "targets sent", Duration::from_secs(20), |_| {
        targets(&robot).len() >= 3
    });
    let mut harness = common::harness(pushlab::app::PushlabApp::new(state), 1.0 / 60.0);
    harness.run_steps(2);
    let projection = harness.state().view.scene.projection();
    let (from, to) = (Point2::new(0.07, 0.0), Point2::new(0.07, 0.05));
    drag(
        &mut harness,
        projection.to_screen(from),
        projection.to_screen(to),
    );
    std::thread::sleep(Duration::from_millis(200));
    harness.run_steps(1);
    let state = &harness.state().state;
    let goal = state.live_drive_shown().unwrap().driving().goal().pose;
    assert!(
        (goal.position - to).norm() < 0.003 && goal.yaw == 0.0,
        "the goal went where it was let go: {goal:?}"
    );
    let choice = &state.live().running().unwrap().choice.drive;
    assert!((Point2::new(choice.goal[0], choice.goal[1]) - to).norm() < 0.003);
    assert_eq!(
        drive(state).halted,
        Some(Halt::Paused),
        "{:?}",
        drive(state)
    );
    let sent = targets(&robot);
    assert!(is_hold_at_pusher(&robot, *sent.last().unwrap()));
    let said = state.status().unwrap_or_default().to_owned();
    assert!(
        said.starts_with("the goal moved to (0.07")
            && said.ends_with(": paused, the pusher held; Arm to push to it"),
        "{said}"
    );

    // Far off the table the box would leave the workspace: refused, said, the goal kept.
    let state = &mut harness.state_mut().state;
    state.apply(Command::Live(LiveCommand::Drive(DriveCommand::SetGoal([
        3.0, 0.05, 0.0,
    ]))));
    let said = state.status().unwrap_or_default().to_owned();
    assert!(
        said.starts_with("the goal was not moved to (3.000 m, 0.050 m): the object there would leave the workspace"),
        "{said}"
    );
    let goal = state.live_drive_shown().unwrap().driving().goal().pose;
    assert!((goal.position - to).norm() < 0.003);
    std::fs::remove_dir_all(&dir).unwrap();
}
