//! The page's test hook in plain Rust: what `window.pushlab.state()` returns, and what
//! `window.pushlab.command(obj)` asks of the app, turned into the state's own commands.
//!
//! Why here and not in `web`: the hook is how end-to-end tests and a teacher's script drive the
//! page, so what it reads and sends must be the app's — the same θ, losses and commands the panels
//! show and send. Plain Rust, it is tested on the desktop; `web` only carries it across to
//! JavaScript.

mod sandbox;

use serde::{Deserialize, Serialize};

pub use self::sandbox::{
    HookPush, HookSandbox, ShownDrive, ShownSandbox, ShownSuggestion, ShownTruth,
};

use pushlab_core::model::OnlineParams;

use super::state::demos::demo::DemoCommand;
use super::state::learning::best_fit::BestFitCommand;
use super::state::learning::landscape::LandscapeCommand;
use super::state::playback::timeline::TimelineCommand;
use super::state::{AppState, Command, OnlineCommand, SessionCommand, TrainingCommand};

/// What is shown, as `state()` returns it (metres, radians; losses as `[pos, rot]`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Shown {
    /// The recording shown, as `folder/name`.
    pub recording: Option<String>,
    pub frame: usize,
    pub frames: usize,
    /// `θ_online` at the frame shown: COM offset x, y and `h`.
    pub theta: Option<[f64; 3]>,
    /// Standard deviations of the COM offset at the frame shown.
    pub sigma_com: Option<[f64; 2]>,
    /// The online loss learned at the frame shown (`pushlab eval --per-frame`'s `online`); `null`
    /// where it was not learned yet — a seek to frame N learns frames 0..N, so N's own loss comes
    /// once the timeline passes it.
    pub online_loss: Option<[f64; 2]>,
    /// The loss of `θ_online(0)` at the frame shown.
    pub fixed_loss: Option<[f64; 2]>,
    pub playing: bool,
    pub learn_while_playing: bool,
    /// Every open recording, as `folder/name`.
    pub open: Vec<String>,
    /// Work is running off the UI thread (loading, training, learning ahead…).
    pub busy: bool,
    /// The share of the running training done, in [0, 1] (what its progress bar shows); `null`
    /// when no model is training.
    pub training: Option<f32>,
    /// The newest load problem, or `null`.
    pub error: Option<String>,
    /// The status line.
    pub status: Option<String>,
    /// The camera pictures shown beside the scene, as the camera panel draws them.
    pub cameras: Vec<ShownCamera>,
    /// The Demos menu's presets, by name (what `command({demo})` takes).
    pub demos: Vec<String>,
    /// The presentation layout's narration line, as it reads now.
    pub narration: String,
    /// The combined model's weight against physics alone for the translation and the rotation at
    /// the frame shown (the Steer tab's and the *Network's weight* plot's); `null` when the run
    /// does not weigh them.
    pub weight: Option<[f64; 2]>,
    /// Frames the page has drawn, and the app's CPU time on the newest (eframe's own figure, ms):
    /// for the guide's performance figures. Only a page fills them.
    pub frames_drawn: Option<u64>,
    pub frame_cpu_ms: Option<f32>,
    /// Push it yourself, while a sandbox is open (`hook::sandbox`).
    pub sandbox: Option<ShownSandbox>,
}

/// One camera picture shown (`state().cameras`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ShownCamera {
    /// The stream's name: a bag's topic, a dataset's image feature, a set's image folder.
    pub name: String,
    /// The stream's frame shown (at or before the scene frame's time); `null` before its first.
    pub frame: Option<usize>,
    /// `[width, height]` of the decoded picture; `null` while it is being decoded or if it failed.
    pub size: Option<[u32; 2]>,
    /// Why the picture cannot be shown, as the panel says it.
    pub problem: Option<String>,
}

/// One call of `command(obj)`: each field that is present is done, in this order.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HookCommand {
    /// Stops what the Cancel buttons stop: a training, a load, the best θ, the landscape.
    pub cancel: Option<bool>,
    pub demo: Option<String>,
    pub open_url: Option<String>,
    pub learn: Option<bool>,
    pub seek: Option<usize>,
    /// Set at the frame shown (after `seek`).
    pub theta: Option<[f64; 3]>,
    pub play: Option<bool>,
    /// A new mystery (`hook::sandbox` has these nine).
    pub sandbox: Option<HookSandbox>,
    pub push: Option<HookPush>,
    /// A pointer path dragging the pusher, `[x, y, t]`: metres, seconds from now.
    pub drag: Option<Vec<[f64; 3]>>,
    pub guess: Option<[f64; 2]>,
    pub reveal: Option<bool>,
    pub suggest: Option<bool>,
    /// Push to goal: the goal `[x, y, yaw]` (world metres and radians), what the controller
    /// plans with (`online`, `fixed`, `physics`, `truth` or `weighted`), and start (true) or stop.
    pub goal: Option<[f64; 3]>,
    pub plan_with: Option<String>,
    pub push_to_goal: Option<bool>,
}

/// What a hook command becomes: the state's commands, and an address to fetch (only a page can).
#[derive(Debug, Default, PartialEq)]
pub struct Translated {
    pub commands: Vec<Command>,
    pub fetch: Option<String>,
}

/// The recording's name as the hook says it: its folder and its name.
pub fn display_name(recording: &pushlab_core::recording::Recording) -> String {
    let folder = recording
        .source
        .parent()
        .and_then(|p| p.file_name())
        .map(|n| n.to_string_lossy().into_owned());
    match folder {
        Some(folder) => format!("{folder}/{}", recording.name),
        None => recording.name.clone(),
    }
}

/// `θ_online` as the hook and links say it: `[x, y, h]`, metres.
pub fn theta_array(theta: OnlineParams) -> [f64; 3] {
    [theta.com_offset[0], theta.com_offset[1], theta.h]
}

/// What `state()` returns for `state`.
pub fn shown(state: &AppState) -> Shown {
    let frame = state.frame();
    let run = state.run();
    let pair = |l: &pushlab_core::model::FrameLoss| [l.pos, l.rot];
    Shown {
        recording: state.recording().map(display_name),
        frame,
        frames: state.recording().map_or(0, |r| r.trajectory.len()),
        theta: state.theta().map(theta_array),
        sigma_com: run.map(|r| {
            let std = r.spread_at(frame).std();
            [std[0], std[1]]
        }),
        online_loss: run.and_then(|r| r.learned().get(frame).copied().flatten().map(|l| pair(&l))),
        fixed_loss: run.and_then(|r| r.fixed().get(frame).map(pair)),
        playing: state.timeline().playing,
        learn_while_playing: state.settings().learn_while_playing,
        open: (state.session().recordings())
            .map(|(_, r)| display_name(r))
            .collect(),
        busy: state.is_busy(),
        training: (state.training().is_running()).then(|| state.training().progress()),
        error: state.session().problems.last().map(|p| p.message.clone()),
        status: state.status().map(str::to_owned),
        cameras: (state
            .cameras()
            .shown(state.timeline().frame_time())
            .into_iter())
        .map(|shown| ShownCamera {
            name: shown.stream.name.clone(),
            frame: shown.frame,
            size: (shown.decoded.as_ref())
                .and_then(|d| d.as_ref().ok())
                .map(|image| [image.width, image.height]),
            problem: (shown.decoded.as_ref())
                .and_then(|d| d.as_ref().err())
                .map(ToString::to_string),
        })
        .collect(),
        demos: (state.demos().names().into_iter())
            .map(str::to_owned)
            .collect(),
        narration: state.narration(),
        weight: run
            .and_then(|r| r.model_weight())
            .map(|w| w.at(frame))
            .map(|w| [w.pos, w.rot]),
        frames_drawn: None,
        frame_cpu_ms: None,
        sandbox: sandbox::shown(state),
    }
}

/// Parses `command(obj)`'s JSON; an unknown field or a wrong type is refused with serde's words.
pub fn parse(json: &str) -> Result<HookCommand, String> {
    serde_json::from_str(json).map_err(|e| format!("pushlab.command: {e}"))
}

/// Turns a hook command into what the menus, keys and sliders send.
pub fn translate(command: &HookCommand, state: &AppState) -> Result<Translated, String> {
    let mut out = Translated::default();
    if command.cancel == Some(true) {
        out.commands.extend([
            Command::Training(TrainingCommand::Cancel),
            Command::Session(SessionCommand::CancelLoading),
            Command::BestFit(BestFitCommand::Cancel),
            Command::Landscape(LandscapeCommand::Cancel),
        ]);
    }
    if let Some(name) = &command.demo {
        let names = state.demos().names();
        let index = names.iter().position(|n| n == name).ok_or_else(|| {
            format!("pushlab.command: no demo named {name:?}; the demos are {names:?}")
        })?;
        out.commands.push(Command::Demo(DemoCommand::Start(index)));
    }
    out.fetch.clone_from(&command.open_url);
    if let Some(learn) = command.learn {
        (out.commands).push(Command::Online(OnlineCommand::SetLearnWhilePlaying(learn)));
    }
    if let Some(frame) = command.seek {
        out.commands
            .push(Command::Timeline(TimelineCommand::SeekTo(frame)));
    }
    if let Some([x, y, h]) = command.theta {
        if ![x, y, h].iter().all(|v| v.is_finite()) || h <= 0.0 {
            return Err(format!(
                "pushlab.command: theta must be [x, y, h] in metres, finite, h > 0; got [{x}, {y}, {h}]"
            ));
        }
        out.commands
            .push(Command::Online(OnlineCommand::SetTheta(OnlineParams {
                com_offset: [x, y],
                h,
            })));
    }
    sandbox::translate(
        sandbox::SandboxFields {
            sandbox: command.sandbox.as_ref(),
            push: command.push.as_ref(),
            drag: command.drag.as_ref(),
            guess: command.guess,
            reveal: command.reveal,
            suggest: command.suggest,
            goal: command.goal,
            plan_with: command.plan_with.as_deref(),
            push_to_goal: command.push_to_goal,
        },
        &mut out.commands,
    )?;
    if let Some(play) = command.play
        && play != state.timeline().playing
    {
        out.commands
            .push(Command::Timeline(TimelineCommand::TogglePlay));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::initial_state;

    fn sample_state() -> AppState {
        initial_state(&[], Default::default())
    }

    #[test]
    fn a_seek_with_learning_on_shows_what_the_run_learned_there() {
        let mut state = sample_state();
        let before = shown(&state);
        assert_eq!(before.frame, 0);
        assert!(
            before.open.len() > 100,
            "the sample data: {}",
            before.open.len()
        );
        let recording = before
            .recording
            .clone()
            .expect("the first push is selected");
        assert!(recording.contains('/'), "{recording}");
        let theta0 = before.theta.expect("a run");

        for json in [r#"{"learn": true, "seek": 41}"#, r#"{"seek": 40}"#] {
            let command = parse(json).expect("parses");
            for c in translate(&command, &state).expect("translates").commands {
                state.apply(c);
            }
            if json.contains("41") {
                assert_eq!(
                    shown(&state).online_loss,
                    None,
                    "frame 41 is not learned yet"
                );
            }
        }
        let after = shown(&state);
        assert_eq!(after.frame, 40);
        assert_ne!(after.theta, Some(theta0), "40 frames learned move θ");
        let run = state.run().expect("a run");
        let theta = run.theta_at(40);
        assert_eq!(
            after.theta,
            Some([theta.com_offset[0], theta.com_offset[1], theta.h])
        );
        let learned = run.learned()[40].expect("frame 40 learned");
        assert_eq!(after.online_loss, Some([learned.pos, learned.rot]));
        assert!(after.fixed_loss.is_some() && after.sigma_com.is_some());
        assert_eq!(after.error, None);
    }

    #[test]
    fn theta_set_by_the_hook_is_the_run_theta_at_the_frame() {
        let mut state = sample_state();
        let command = parse(r#"{"theta": [0.01, -0.02, 0.05]}"#).expect("parses");
        for c in translate(&command, &state).expect("translates").commands {
            state.apply(c);
        }
        let theta = shown(&state).theta.expect("a run");
        assert!((theta[0] - 0.01).abs() < 1e-12 && (theta[1] + 0.02).abs() < 1e-12);
        assert!((theta[2] - 0.05).abs() < 1e-12, "{theta:?}");
    }

    #[test]
    fn bad_commands_are_refused_by_name() {
        let state = sample_state();
        let unknown = parse(r#"{"jump": 3}"#).expect_err("no such field");
        assert!(unknown.contains("unknown field `jump`"), "{unknown}");
        let demo = translate(&parse(r#"{"demo": "nope"}"#).expect("parses"), &state)
            .expect_err("no such demo");
        assert!(demo.contains("no demo named \"nope\""), "{demo}");
        let theta = translate(&parse(r#"{"theta": [0, 0, -1]}"#).expect("parses"), &state)
            .expect_err("h must be positive");
        assert!(theta.contains("h > 0"), "{theta}");
    }

    #[test]
    fn play_toggles_only_when_it_changes_something() {
        let state = sample_state();
        let pause = translate(&parse(r#"{"play": false}"#).expect("parses"), &state);
        assert_eq!(pause.expect("translates").commands, Vec::new());
        let play = translate(&parse(r#"{"play": true}"#).expect("parses"), &state);
        assert_eq!(
            play.expect("translates").commands,
            vec![Command::Timeline(TimelineCommand::TogglePlay)]
        );
    }
}
