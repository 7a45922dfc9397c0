//! Beyond the paper in the app, driven through the UI: after learning, the Steer tab gives ± for each
//! component and the scene's COM ellipse shrinks from the prior's; choosing Gauss–Newton changes
//! `θ_online(t)`; the what-if ghosts follow the sliders.

use crate::common;

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use pushlab::app::PushlabApp;
use pushlab::app::state::Command;
use pushlab::app::state::OnlineCommand;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab_core::learn::Optimizer;
use pushlab_core::learn::uncertainty::ComSpreadParts;
use pushlab_core::model::OnlineParams;

fn theta(harness: &Harness<'_, PushlabApp>) -> OnlineParams {
    harness.state().state.theta().expect("a run")
}

/// The COM ellipse's half-axes at the frame shown, metres.
fn ellipse_axes(harness: &Harness<'_, PushlabApp>) -> [f64; 2] {
    let state = &harness.state().state;
    let run = state.run().expect("a run");
    run.spread_at(state.frame()).ellipse_95().0
}

/// The ± values the Steer tab shows, millimetres.
fn plus_minus(harness: &Harness<'_, PushlabApp>) -> Vec<f64> {
    harness
        .query_all_by_label_contains("± ")
        .filter_map(|node| {
            let node = node.accesskit_node();
            node.label()
                .or_else(|| node.value())
                .and_then(|l| l.trim_start_matches("± ").parse::<f64>().ok())
        })
        .collect()
}

#[test]
fn learning_shrinks_the_com_ellipse_and_the_steer_tab_gives_plus_minus() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    harness.run_steps(2);
    let prior = ellipse_axes(&harness);
    let before = plus_minus(&harness);
    assert_eq!(before.len(), 3, "± for COM x, COM y and h: {before:?}");
    common::step_frames(&mut harness, 40);
    let learned = ellipse_axes(&harness);
    assert!(
        learned[0] < 0.5 * prior[0] && learned[1] > 0.0,
        "ellipse half-axes {learned:?} after 40 frames, prior {prior:?}"
    );
    let after = plus_minus(&harness);
    assert_eq!(after.len(), 3);
    for (a, b) in after.iter().zip(&before) {
        assert!(a < b, "± after learning {after:?}, before {before:?}");
    }
    // The legend's toggle hides the ellipse layer.
    assert!(harness.state().state.settings().layers.com_ellipse);
    // Scrubbing back restores the earlier, wider ellipse exactly.
    harness
        .state_mut()
        .state
        .apply(Command::Timeline(TimelineCommand::SeekTo(0)));
    harness.run_steps(1);
    assert_eq!(ellipse_axes(&harness), prior);
}

#[test]
fn choosing_gauss_newton_in_the_steer_tab_changes_what_is_learned() {
    let mut gd = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut gd, 30);
    let mut gn = common::app_on_sample("box1-paper-ur-front");
    gn.run_steps(1);
    gn.get_by_label("Gauss–Newton").click();
    gn.run_steps(2);
    assert_eq!(
        gn.state().state.settings().online.optimizer,
        Optimizer::GaussNewton
    );
    common::step_frames(&mut gn, 30);
    assert_ne!(theta(&gd), theta(&gn));
    // Back to the paper's rule from frame 10: the run re-learns from there with gradient descent.
    gn.state_mut()
        .state
        .apply(Command::Timeline(TimelineCommand::SeekTo(0)));
    gn.run_steps(1);
    gn.get_by_label("Gradient descent (paper)").click();
    gn.run_steps(1);
    common::step_frames(&mut gn, 30);
    assert_eq!(
        theta(&gd),
        theta(&gn),
        "the same rule from frame 0 learns the same θ"
    );
}

#[test]
fn what_if_ghosts_follow_the_sliders_and_k_is_chosen_in_steer() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut harness, 10);
    let state = &harness.state().state;
    let before = state.what_if().expect("a run").clone();
    // k = 20 by default, each step the model's horizon long, up to the end of the push.
    let run = state.run().expect("a run");
    let frames = state
        .recording()
        .expect("a recording")
        .trajectory
        .frames
        .len();
    let expected = 20.min((frames - 1 - state.frame()) / run.horizon());
    assert!(expected >= 5, "a push with room to roll ahead");
    assert_eq!(before.poses.len(), expected);
    assert!(
        harness
            .query_by_label_contains(&format!("After {expected} steps"))
            .is_some(),
        "the final pose error is shown"
    );
    let mut moved = theta(&harness);
    moved.com_offset[0] += 0.05;
    harness
        .state_mut()
        .state
        .apply(Command::Online(OnlineCommand::SetTheta(moved)));
    harness.run_steps(1);
    let after = harness.state().state.what_if().expect("a run");
    assert_eq!(after.poses.len(), expected);
    assert_ne!(before.poses.last(), after.poses.last(), "the ghosts moved");
    harness
        .state_mut()
        .state
        .apply(Command::Online(OnlineCommand::SetWhatIfSteps(3)));
    harness.run_steps(1);
    assert_eq!(
        harness.state().state.what_if().expect("a run").poses.len(),
        3
    );
    assert!(harness.query_by_label_contains("After 3 steps").is_some());
}

#[test]
fn the_inspector_gives_the_what_if_final_pose_error() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    common::step_frames(&mut harness, 10);
    harness.get_by_label("Inspect").click();
    harness.run_steps(2);
    let state = &harness.state().state;
    let rollout = state.what_if().expect("a run");
    let trajectory = &state.recording().expect("a recording").trajectory;
    let (offset, _) = rollout.final_error(trajectory).expect("a rollout");
    assert!(
        offset > 1e-4,
        "a learned model still drifts from the recording"
    );
    let shown = format!("{:.3} mm", offset * 1e3);
    assert!(
        harness
            .query_by_label_contains("final position error")
            .is_some(),
        "the inspector's what-if section"
    );
    assert!(
        harness.query_by_label(&shown).is_some(),
        "the inspector shows {shown}"
    );
    // A new θ moves the rollout, and the inspector follows.
    let mut moved = theta(&harness);
    moved.com_offset[1] -= 0.05;
    harness
        .state_mut()
        .state
        .apply(Command::Online(OnlineCommand::SetTheta(moved)));
    harness.run_steps(2);
    let state = &harness.state().state;
    let trajectory = &state.recording().expect("a recording").trajectory;
    let (after, _) = state
        .what_if()
        .and_then(|r| r.final_error(trajectory))
        .expect("a rollout");
    assert_ne!(format!("{:.3} mm", after * 1e3), shown);
    assert!(
        harness
            .query_by_label(&format!("{:.3} mm", after * 1e3))
            .is_some()
    );
}

#[test]
fn the_steer_tab_says_what_the_com_spread_is_made_of() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    harness.run_steps(2);
    // Nothing learned yet: the prior's spread, nothing from a misfit or a path.
    let prior = harness
        .state()
        .state
        .run()
        .expect("a run")
        .spread_at(0)
        .com_parts();
    assert_eq!(prior.drift_m, 0.0);
    assert!(
        harness
            .query_by_label_contains(&format!(
                "COM σ at frame 0 (mm): frames learned {:.1},",
                prior.frames_m * 1e3
            ))
            .is_some()
    );
    common::step_frames(&mut harness, 40);
    let state = &harness.state().state;
    let run = state.run().expect("a run");
    let parts = run.spread_at(run.frontier()).com_parts();
    let exact = run.posterior().com_spread_parts();
    assert!(
        (parts.drift_m - exact.drift_m).abs() < 1e-6,
        "{parts:?} against {exact:?}"
    );
    // The COM sits 71 mm from θ_online(0) on these pushes: the estimate is still sliding toward it.
    assert!(
        parts.drift_m > 1e-3,
        "the estimate's drift after 40 frames: {parts:?}"
    );
    // The three parts are the ellipse's: their squares add up to its mean COM variance.
    let [xx, _, yy] = run.spread_at(run.frontier()).com_cov.map(f64::from);
    let sum = parts.frames_m.powi(2) + parts.misfit_m.powi(2) + parts.drift_m.powi(2);
    assert!(
        (sum - (xx + yy) / 2.0).abs() < 1e-6 * sum,
        "{parts:?} against the spread shown"
    );
    let shown = |at: &str, parts: ComSpreadParts| {
        format!(
            "COM σ at {at} (mm): frames learned {:.1},\nmodel misfit {:.1}, estimate still moving \
             {:.1}",
            parts.frames_m * 1e3,
            parts.misfit_m * 1e3,
            parts.drift_m * 1e3,
        )
    };
    let newest = shown(&format!("frame {}", run.frontier()), parts);
    assert!(
        harness.query_by_label(&newest).is_some(),
        "Steer shows {newest}"
    );
    // Scrubbed back, the parts are those of the frame shown, the ellipse's there.
    let frontier = run.frontier();
    harness
        .state_mut()
        .state
        .apply(Command::Timeline(TimelineCommand::SeekTo(10)));
    harness.run_steps(2);
    let run = harness.state().state.run().expect("a run");
    assert_eq!(run.frontier(), frontier, "seeking back unlearns nothing");
    let back = run.spread_at(10).com_parts();
    assert!(back.drift_m < parts.drift_m, "{back:?} against {parts:?}");
    let then = shown("frame 10", back);
    assert!(
        harness.query_by_label(&then).is_some(),
        "Steer shows {then}"
    );
    assert!(harness.query_by_label(&newest).is_none());
}

#[test]
fn the_steer_tab_finds_the_best_theta_for_the_push_and_steers_there() {
    let mut harness = common::app_on_sample("box1-paper-ur-front");
    harness.run_steps(2);
    harness.get_by_label("Find the best θ").click();
    common::run_until(&mut harness, "the best θ is found", |app| {
        let state = &app.state;
        (state.run()).is_some_and(|run| state.best_fit().result_for(run).is_some())
    });
    let state = &harness.state().state;
    let run = state.run().expect("a run");
    let fit = (state.best_fit().result_for(run))
        .and_then(|r| r.fit)
        .expect("a best fit");
    // The sample set knows its COM: the tab says how far the best one is from it.
    let truth = state
        .recording()
        .and_then(|r| r.setting.com_offset)
        .expect("a true COM");
    let said = format!("{:.1} mm from the true COM", fit.com_error_m(truth) * 1e3);
    assert!(harness.query_by_label_contains(&said).is_some(), "{said}");
    assert_ne!(theta(&harness), fit.theta);
    harness.get_by_label("Use it here").click();
    harness.run_steps(2);
    assert_eq!(theta(&harness), fit.theta);
    // The scene marks the best COM with a ring, a layer the legend switches.
    assert!(harness.state().state.settings().layers.com_best);
    harness.get_by_label("Show layers").click();
    harness.run_steps(2);
    harness.get_by_label_contains("Best θ's COM, ring").click();
    harness.run_steps(2);
    assert!(!harness.state().state.settings().layers.com_best);
}
