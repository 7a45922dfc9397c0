//! "What would the controller do here" on a replayed push: off by default; switched on, the app
//! plans the core's step (`control::replay`) from the frame shown with θ as the run learned it
//! there, toward where the push ends, to the bit; scrubbed to another frame it plans again; at
//! the last frame it holds; the Steer tab says the step in words.

use egui_kittest::kittest::Queryable;
use pushlab::app::state::Command;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab_core::control::Phase;
use pushlab_core::control::replay::{ReplayedPush, replay_pacing};

use crate::common;

#[test]
fn the_layer_plans_the_cores_step_from_the_frame_shown_and_steer_says_it() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    {
        let state = &mut harness.state_mut().state;
        for _ in 0..12 {
            state.apply(Command::Timeline(TimelineCommand::Step(1)));
        }
        assert!(state.controller_here().is_none(), "off by default");
        let mut layers = state.settings().layers.clone();
        layers.controller = true;
        state.apply(Command::SetLayers(layers));
    }
    let state = &harness.state().state;
    let frame = state.frame();
    assert_eq!(frame, 12);
    let (goal, plan) = state.controller_here().expect("planned").clone();
    let run = state.run().expect("a run");
    let recording = state.recording().expect("a recording");
    let outline = recording.setting.object.outline().expect("an outline");
    let push = ReplayedPush {
        trajectory: run.trajectory(),
        outline: &outline,
        pusher_radius: recording.setting.pusher_radius,
        model: run.model().as_ref(),
        horizon: run.horizon(),
        pacing: replay_pacing(run.trajectory()).expect("a pace"),
    };
    let theta = run.theta_at(frame);
    assert_ne!(theta, run.theta_at(0), "θ as learned by frame 12");
    assert_eq!(push.plan_at(frame, &theta), Some((goal, plan.clone())));
    let last = recording.trajectory.frames.last().expect("frames");
    assert_eq!(goal.pose, last.object, "heads for where the push ends");
    let chosen = plan.push.expect("a push");

    // The Steer tab says it.
    harness.run_steps(2);
    let said = format!("a push of {:.0} mm", chosen.length_m * 1e3);
    assert!(
        harness.query_all_by_label_contains(&said).next().is_some(),
        "Steer says {said}"
    );

    // Another frame, another step; at the last, the object is where the push ends: hold.
    let end = harness
        .state()
        .state
        .recording()
        .expect("a recording")
        .trajectory
        .len()
        - 1;
    let state = &mut harness.state_mut().state;
    state.apply(Command::Timeline(TimelineCommand::SeekTo(end)));
    let (_, at_end) = state.controller_here().expect("planned at the end");
    assert_eq!(at_end.phase, Some(Phase::Holding));
    harness.run_steps(2);
    assert!(
        (harness.query_all_by_label_contains("Hold: the object is within tolerance"))
            .next()
            .is_some()
    );
}
