//! The scene's camera and legend, driven through the UI: following keeps the object in view while a
//! push plays to its end, zooming keeps following, panning frees the camera, "Fit all" shows the whole
//! push, and the legend is folded until asked for and never covers the object.

use crate::common;

use eframe::egui;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use pushlab::app::PushlabApp;
use pushlab::app::camera_mode::CameraMode;
use pushlab::app::state::Command;
use pushlab::app::state::playback::timeline::TimelineCommand;
use pushlab_core::geometry::Pose2;

/// The object's outline at `pose` on the screen, as the scene drew it last frame.
fn object_on_screen(harness: &Harness<'_, PushlabApp>, pose: &Pose2) -> Vec<egui::Pos2> {
    let app = harness.state();
    let outline = app
        .state
        .recording()
        .expect("a recording")
        .setting
        .object
        .outline()
        .expect("an outline");
    let projection = app.view.scene.projection();
    outline
        .vertices()
        .iter()
        .map(|v| projection.to_screen(pose.point_in_world(*v)))
        .collect()
}

/// The object's pose at the frame shown.
fn pose_now(harness: &Harness<'_, PushlabApp>) -> Pose2 {
    let state = &harness.state().state;
    state.recording().expect("a recording").trajectory.frames[state.frame()].object
}

/// Plays to the end, checking after every frame that the object's whole footprint lies in the part
/// of the scene the camera may use (right of the legend when it is open). Returns the frames seen.
fn play_to_the_end_keeping_the_object_in_view(harness: &mut Harness<'_, PushlabApp>) -> usize {
    harness
        .state_mut()
        .state
        .apply(Command::Timeline(TimelineCommand::SetSpeed(4.0)));
    harness.get_by_label("Play").click();
    let mut frames = 0;
    for _ in 0..400 {
        harness.run_steps(1);
        let viewport = harness.state().view.scene.viewport();
        for corner in object_on_screen(harness, &pose_now(harness)) {
            assert!(
                viewport.contains(corner),
                "frame {}: the object's corner {corner:?} is outside the view {viewport:?}",
                harness.state().state.frame()
            );
        }
        frames += 1;
        if !harness.state().state.timeline().playing {
            break;
        }
    }
    let state = &harness.state().state;
    assert_eq!(
        state.frame(),
        state.timeline().last_frame(),
        "played to the end"
    );
    frames
}

#[test]
fn following_keeps_the_object_in_view_to_the_end_of_a_push_and_keeps_the_zoom() {
    let mut harness = common::app_on_sample("box1-paper-center-front");
    harness.run_steps(2);
    assert_eq!(
        harness.state().view.scene.mode,
        CameraMode::Follow,
        "the default"
    );
    // Zoom in over the scene: the view stays following, at the new zoom.
    let scene = harness.state().view.scene.rect();
    let before = harness.state().view.scene.camera.scale;
    harness.hover_at(scene.center());
    harness.event(egui::Event::Zoom(2.5));
    harness.run_steps(1);
    let zoomed = harness.state().view.scene.camera.scale;
    assert!((zoomed / before - 2.5).abs() < 1e-3, "{before} → {zoomed}");
    assert!(play_to_the_end_keeping_the_object_in_view(&mut harness) > 20);
    let view = &harness.state().view.scene;
    assert_eq!(view.mode, CameraMode::Follow);
    assert_eq!(view.camera.scale, zoomed, "following kept the user's zoom");

    // The same with the legend open: the object stays right of it.
    harness.get_by_label("Show layers").click();
    harness.run_steps(1);
    harness.get_by_label("Start").click();
    play_to_the_end_keeping_the_object_in_view(&mut harness);
}

#[test]
fn the_object_leaves_a_free_camera_and_fit_all_brings_the_whole_push_back() {
    let mut harness = common::app_on_sample("box1-paper-center-front");
    harness.run_steps(2);
    // Drag the empty scene: the camera is freed where the user put it.
    let scene = harness.state().view.scene.rect();
    let from = scene.left_top() + egui::vec2(40.0, 40.0);
    harness.drag_at(from);
    harness.run_steps(1);
    harness.hover_at(from + egui::vec2(-150.0, 60.0));
    harness.run_steps(1);
    harness.drop_at(from + egui::vec2(-150.0, 60.0));
    harness.run_steps(1);
    let view = &harness.state().view.scene;
    assert_eq!(view.mode, CameraMode::Free);
    let camera = view.camera;
    harness.get_by_label("Play").click();
    harness.run_steps(20);
    assert_eq!(
        harness.state().view.scene.camera,
        camera,
        "a free camera stays put"
    );

    // "Fit all": every position of the push is in view.
    harness.get_by_label("Fit all").click();
    harness.run_steps(2);
    let app = harness.state();
    let projection = app.view.scene.projection();
    let viewport = app.view.scene.viewport();
    let frames = &app
        .state
        .recording()
        .expect("a recording")
        .trajectory
        .frames;
    for f in frames {
        for p in [f.robot, f.object.position] {
            assert!(viewport.contains(projection.to_screen(p)), "{p:?} outside");
        }
    }
    // F follows again.
    harness.key_press(egui::Key::F);
    harness.run_steps(1);
    assert_eq!(harness.state().view.scene.mode, CameraMode::Follow);
}

#[test]
fn the_legend_is_folded_until_asked_for_and_its_toggles_change_the_layers() {
    let mut harness = common::app_on_sample("box1-paper-center-front");
    harness.run_steps(2);
    assert!(
        harness.query_by_label("Predicted: online θ").is_none(),
        "folded by default"
    );
    harness.get_by_label("Show layers").click();
    harness.run_steps(1);
    assert!(harness.state().state.settings().layers.predicted_fixed);
    harness.get_by_label("Predicted: fixed θ(0)").click();
    harness.run_steps(1);
    assert!(
        !harness.state().state.settings().layers.predicted_fixed,
        "the toggle sent its command"
    );
    // Open, it takes the scene's left strip and the camera uses the rest.
    let view = &harness.state().view.scene;
    assert!(view.viewport().left() >= view.rect().left() + 200.0);
    harness.get_by_label("Hide layers").click();
    harness.run_steps(1);
    assert!(harness.query_by_label("Predicted: online θ").is_none());
    assert_eq!(
        harness.state().view.scene.viewport(),
        harness.state().view.scene.rect()
    );
}
