//! The sandbox through the page's hook: `command({sandbox: {seed, object}})`, `{push: {face,
//! offset, angle, length}}`, `{drag: [[x, y, t], …]}`, `{guess: [x, y]}`, `{reveal: true}`,
//! `{suggest: true}`, Push to goal's `{goal: [x, y, yaw]}`, `{plan_with: "online"}` and
//! `{push_to_goal: true}` (false stops it), and what `state().sandbox` shows. A class's script and the browser tests
//! push the mystery as a student does, through the same commands the scene's handles send.

use serde::{Deserialize, Serialize};

use pushlab_core::control::PlanWith;
use pushlab_core::recording::PushSide;
use pushlab_core::sandbox::{MysteryObject, PushChoice, ScoreCard, push_of_shape};

use crate::app::state::learning::next_push::{Candidates, NextPushCommand};
use crate::app::state::sources::sandbox::SandboxCommand;
use crate::app::state::{AppState, Command};

/// `command({sandbox: …})`: a new mystery.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HookSandbox {
    pub seed: u64,
    /// `box`, `t` or `ellipse`.
    pub object: String,
    #[serde(default)]
    pub noise: bool,
    #[serde(default)]
    pub challenge: bool,
    /// A teacher's hidden COM offset, object frame, metres.
    pub com: Option<[f64; 2]>,
}

/// `command({push: …})`, and each of `state().sandbox.suggested`: a push on the object as
/// `pushlab suggest` names one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HookPush {
    /// The face, as `setting.json`'s `push_side`: front, left, back or right.
    pub face: String,
    /// Metres from the face's middle, positive to the pusher's left.
    pub offset: f64,
    /// Degrees from the face's normal, counter-clockwise positive.
    pub angle: f64,
    /// Metres the pusher goes once it touches.
    pub length: f64,
}

impl From<PushChoice> for HookPush {
    fn from(choice: PushChoice) -> Self {
        Self {
            face: choice.face.name().to_owned(),
            offset: choice.offset_m,
            angle: choice.angle_deg,
            length: choice.length_m,
        }
    }
}

/// A push the ranking suggests, and the COM σ it is expected to leave (metres).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShownSuggestion {
    #[serde(flatten)]
    pub push: HookPush,
    pub com_std_after: f64,
}

/// The hidden values, after the reveal.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShownTruth {
    pub com: [f64; 2],
    pub h: f64,
}

/// `state().sandbox`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShownSandbox {
    pub seed: u64,
    pub object: String,
    /// Pushes made (finished).
    pub pushes: usize,
    /// A push is being made now.
    pub pushing: bool,
    pub guess: Option<[f64; 2]>,
    pub revealed: bool,
    pub challenge: bool,
    /// After the reveal only.
    pub truth: Option<ShownTruth>,
    pub score: Option<ScoreCard>,
    /// The pusher, world metres, and the object's pose `[x, y, yaw]` now.
    pub pusher: [f64; 2],
    pub object_pose: [f64; 3],
    /// The ranking's best pushes from where learning stands (after `command({suggest: true})`
    /// has finished on the push shown), best first.
    pub suggested: Vec<ShownSuggestion>,
    /// The sandbox's own work on the UI thread in the newest frame that made frames (simulate,
    /// grow, learn; a push's review at its end), and the longest since it opened, ms.
    pub step_ms: Option<f64>,
    pub longest_step_ms: f64,
    /// Push to goal: the goal `[x, y, yaw]` (world), what the controller plans with, whether it
    /// is pushing now, and how its last push to the goal ended.
    pub goal: Option<[f64; 3]>,
    pub plan_with: String,
    pub driving: bool,
    pub last_drive: Option<ShownDrive>,
}

/// How a push to the goal ended.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShownDrive {
    pub reached: bool,
    /// Seconds of pushing.
    pub time_s: f64,
    pub plan_with: String,
}

/// What `state().sandbox` shows, while there is a sandbox.
pub fn shown(state: &AppState) -> Option<ShownSandbox> {
    let session = state.sandbox()?;
    let sandbox = session.sandbox();
    let mystery = sandbox.mystery();
    let pose = sandbox.object_pose();
    let pusher = sandbox.pusher();
    Some(ShownSandbox {
        seed: mystery.seed,
        object: mystery.object.name().to_owned(),
        pushes: sandbox.made().len(),
        pushing: sandbox.is_pushing(),
        guess: session.guess(),
        revealed: session.revealed(),
        challenge: session.challenge(),
        truth: session.revealed().then_some(ShownTruth {
            com: mystery.hidden.com_offset,
            h: mystery.h,
        }),
        score: session.score().cloned(),
        pusher: [pusher.x, pusher.y],
        object_pose: [pose.position.x, pose.position.y, pose.yaw],
        suggested: suggested(state),
        step_ms: session.step_ms().0,
        longest_step_ms: session.step_ms().1,
        goal: session.goal().map(|g| [g.position.x, g.position.y, g.yaw]),
        plan_with: session.plan_with().name().to_owned(),
        driving: session.driving().is_some(),
        last_drive: session
            .last_drive()
            .map(|(reached, time_s, with)| ShownDrive {
                reached,
                time_s,
                plan_with: with.name().to_owned(),
            }),
    })
}

/// The ranking's suggestions for the push shown, as pushes the sandbox can make.
fn suggested(state: &AppState) -> Vec<ShownSuggestion> {
    let (Some(run), Some(session)) = (state.run(), state.sandbox()) else {
        return Vec::new();
    };
    let Some(result) = state.next_push().result_for(run) else {
        return Vec::new();
    };
    if !matches!(result.candidates, Candidates::Grid { .. }) {
        return Vec::new();
    }
    let outline = &session.sandbox().mystery().sim.outline;
    (result.ranking.suggestions.iter())
        .filter_map(|s| {
            let choice = push_of_shape(outline, s.shape.as_ref()?)?;
            Some(ShownSuggestion {
                push: choice.into(),
                com_std_after: s.com_std_after_m,
            })
        })
        .collect()
}

/// The sandbox's part of `command(obj)` (fields of [`super::HookCommand`]).
#[derive(Clone, Copy, Debug)]
pub struct SandboxFields<'a> {
    pub sandbox: Option<&'a HookSandbox>,
    pub push: Option<&'a HookPush>,
    pub drag: Option<&'a Vec<[f64; 3]>>,
    pub guess: Option<[f64; 2]>,
    pub reveal: Option<bool>,
    /// Rank the next push from where learning stands (the Steer tab's Suggest the next push).
    pub suggest: Option<bool>,
    pub goal: Option<[f64; 3]>,
    pub plan_with: Option<&'a str>,
    pub push_to_goal: Option<bool>,
}

/// Turns the sandbox's fields into the commands the sandbox's window and handles send.
pub fn translate(fields: SandboxFields<'_>, out: &mut Vec<Command>) -> Result<(), String> {
    if let Some(start) = fields.sandbox {
        let object: MysteryObject = start
            .object
            .parse()
            .map_err(|e| format!("pushlab.command: sandbox.object: {e}"))?;
        out.push(Command::Sandbox(SandboxCommand::Start {
            seed: start.seed,
            object: Some(object),
            noise: start.noise,
            challenge: start.challenge,
            com: start.com,
        }));
    }
    if let Some(push) = fields.push {
        let face: PushSide = push.face.parse().map_err(|_| {
            format!(
                "pushlab.command: push.face {:?}: expected front, left, back or right",
                push.face
            )
        })?;
        if ![push.offset, push.angle, push.length]
            .iter()
            .all(|v| v.is_finite())
        {
            return Err("pushlab.command: push: offset, angle and length must be finite".into());
        }
        out.push(Command::Sandbox(SandboxCommand::Push(PushChoice {
            face,
            offset_m: push.offset,
            angle_deg: push.angle,
            length_m: push.length,
        })));
    }
    if let Some(points) = fields.drag {
        out.push(Command::Sandbox(SandboxCommand::Drag(points.clone())));
    }
    if let Some(at) = fields.guess {
        if !at.iter().all(|v| v.is_finite()) {
            return Err("pushlab.command: guess must be [x, y], finite metres".into());
        }
        out.push(Command::Sandbox(SandboxCommand::Guess(at)));
    }
    if fields.reveal == Some(true) {
        out.push(Command::Sandbox(SandboxCommand::Reveal));
    }
    if fields.suggest == Some(true) {
        out.push(Command::NextPush(NextPushCommand::Suggest));
    }
    if let Some(goal) = fields.goal {
        if !goal.iter().all(|v| v.is_finite()) {
            return Err(
                "pushlab.command: goal must be [x, y, yaw], finite metres and radians".into(),
            );
        }
        out.push(Command::Sandbox(SandboxCommand::SetGoal(goal)));
    }
    if let Some(name) = fields.plan_with {
        let with = PlanWith::from_name(name).ok_or_else(|| {
            format!(
                "pushlab.command: plan_with {name:?}: expected {}",
                PlanWith::expected()
            )
        })?;
        out.push(Command::Sandbox(SandboxCommand::SetPlanWith(with)));
    }
    match fields.push_to_goal {
        Some(true) => out.push(Command::Sandbox(SandboxCommand::PushToGoal)),
        Some(false) => out.push(Command::Sandbox(SandboxCommand::StopPushToGoal)),
        None => {}
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use pushlab_core::sandbox::{Mystery, PointerPath, Sandbox, recorded_pushes};

    use super::*;
    use crate::app::hook::{parse, shown as shown_all, translate as translate_all};
    use crate::app::initial_state;

    fn send(state: &mut AppState, json: &str) -> Result<(), String> {
        let command = parse(json)?;
        for c in translate_all(&command, state)?.commands {
            state.apply(c);
        }
        Ok(())
    }

    /// Lets the app's frames pass until nothing runs and no push is being made.
    fn settle(state: &mut AppState) {
        for _ in 0..20_000 {
            state.advance(0.1);
            let pushing = state.sandbox().is_some_and(|s| s.sandbox().is_pushing());
            if !pushing && !state.is_busy() && !state.next_push().is_running() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        panic!("never settled: {:?}", state.status());
    }

    #[test]
    fn a_hook_drag_makes_the_simulators_poses_and_a_suggested_push_is_made() {
        let mut state = initial_state(&[], Default::default());
        send(&mut state, r#"{"sandbox": {"seed": 12, "object": "box"}}"#).unwrap();
        let [x, y] = shown_all(&state).sandbox.unwrap().pusher;
        let points = [
            [x, y, 0.0],
            [x + 0.2, y - 0.03, 5.0],
            [x + 0.26, y - 0.05, 7.0],
        ];
        send(&mut state, &format!(r#"{{"drag": {points:?}}}"#)).unwrap();
        let mut core = Sandbox::new(Mystery::draw(12, MysteryObject::Box).unwrap(), None);
        let made = recorded_pushes(
            &core
                .drag(PointerPath::from_points(&points).unwrap())
                .unwrap(),
        );
        assert_eq!(*state.recording().unwrap().trajectory, made[0]);
        let after_drag = shown_all(&state).sandbox.unwrap();
        assert_eq!((after_drag.pushes, after_drag.pushing), (1, false));
        assert!(after_drag.truth.is_none(), "hidden until the reveal");

        // The ranking from where learning stands, then its best push made.
        assert!(after_drag.suggested.is_empty(), "nothing ranked yet");
        send(&mut state, r#"{"suggest": true}"#).unwrap();
        settle(&mut state);
        let suggested = shown_all(&state).sandbox.unwrap().suggested;
        assert!(suggested.len() > 10, "the grid ranked: {}", suggested.len());
        let best = &suggested[0];
        assert!(
            suggested
                .iter()
                .all(|s| s.com_std_after >= best.com_std_after)
        );
        let json = serde_json::json!({"push": best.push}).to_string();
        send(&mut state, &json).unwrap();
        settle(&mut state);
        let second = shown_all(&state).sandbox.unwrap();
        assert_eq!(second.pushes, 2);
        let run = state.run().unwrap();
        assert_eq!(run.continued_from(), Some("push 0"));

        send(&mut state, r#"{"guess": [0.0, 0.01], "reveal": true}"#).unwrap();
        let revealed = shown_all(&state).sandbox.unwrap();
        let truth = revealed.truth.unwrap();
        assert_eq!(
            truth.com,
            state
                .sandbox()
                .unwrap()
                .sandbox()
                .mystery()
                .hidden
                .com_offset
        );
        let score = revealed.score.unwrap();
        assert_eq!(score.pushes, 2);
        assert_eq!(score.guess_m, Some([0.0, 0.01]));
    }

    #[test]
    fn bad_sandbox_commands_are_refused_by_name() {
        let mut state = initial_state(&[], Default::default());
        let e = send(&mut state, r#"{"sandbox": {"seed": 1, "object": "cube"}}"#).unwrap_err();
        assert!(
            e.contains("sandbox.object: unknown mystery object 'cube'"),
            "{e}"
        );
        let e = send(
            &mut state,
            r#"{"push": {"face": "top", "offset": 0, "angle": 0, "length": 0.1}}"#,
        )
        .unwrap_err();
        assert!(
            e.contains("push.face \"top\": expected front, left, back or right"),
            "{e}"
        );
        let e = send(&mut state, r#"{"push": {"face": "front"}}"#).unwrap_err();
        assert!(e.contains("missing field `offset`"), "{e}");
        let e = send(&mut state, r#"{"plan_with": "magic"}"#).unwrap_err();
        assert!(
            e.contains(r#"plan_with "magic": expected online, fixed, physics, truth or weighted"#),
            "{e}"
        );
    }

    #[test]
    fn the_hook_pushes_the_mystery_to_a_goal_and_says_how_it_went() {
        let mut state = initial_state(&[], Default::default());
        send(&mut state, r#"{"sandbox": {"seed": 4, "object": "box"}}"#).unwrap();
        let [x, y, yaw] = shown_all(&state).sandbox.unwrap().object_pose;
        let goal = [x + 0.08, y, yaw];
        send(
            &mut state,
            &format!(r#"{{"goal": {goal:?}, "plan_with": "fixed", "push_to_goal": true}}"#),
        )
        .unwrap();
        let shown = shown_all(&state).sandbox.unwrap();
        assert_eq!(shown.goal, Some(goal));
        assert_eq!(shown.plan_with, "fixed");
        assert!(shown.driving);
        for _ in 0..3000 {
            state.advance(0.1);
            if state.sandbox().unwrap().driving().is_none() {
                break;
            }
        }
        let shown = shown_all(&state).sandbox.unwrap();
        let drive = shown.last_drive.expect("the push to the goal ended");
        assert!(drive.reached, "{drive:?}: {:?}", state.status());
        assert_eq!(drive.plan_with, "fixed");
        assert!(!shown.driving);
        let [ox, oy, oyaw] = shown.object_pose;
        assert!(
            (ox - goal[0]).hypot(oy - goal[1]) < 0.01 && (oyaw - goal[2]).abs() < 3f64.to_radians(),
            "the object {:?} at the goal {goal:?}",
            shown.object_pose
        );
        // Stopping a push to the goal that is not running changes nothing.
        send(&mut state, r#"{"push_to_goal": false}"#).unwrap();
        assert_eq!(shown_all(&state).sandbox.unwrap().last_drive, Some(drive));
    }
}
