//! The scene: a top view of the table in metres, with the robot, the object's true and predicted
//! footprints, the COM estimates and the contact.
//!
//! Split like rerun's views: `camera` (where the view looks and how it follows, fits or stays),
//! `interaction` (drags, pan, zoom), `draw` (shapes through the camera's projection) and `legend`
//! (the layer toggles). This module puts them together for one frame; every prediction it draws
//! comes from the state (`AppState::predictions`), and every change goes out as a [`Command`] —
//! only the camera, which is the view's own, is changed here.

pub mod camera;
mod content;
pub mod draw;
mod drive_goal;
mod goal_handles;
pub mod hover;
pub mod interaction;
pub mod legend;
mod plan;
pub mod sandbox;
mod view;

use eframe::egui::{self, Sense};
use nalgebra::Point2;
use pushlab_core::geometry::{Outline, Pose2};

use self::camera::{Camera, Projection, WorldBox};
use self::content::{Content, Target};
use self::draw::FootprintStyle;
use self::interaction::Markers;
use self::sandbox::{Grab, Grips};
pub use self::view::{Drag, SceneView};
use crate::app::camera_mode::CameraMode;
use crate::app::colors::{self, Palette};
use crate::app::state::learning::next_push;
use crate::app::state::{AppState, Command};

/// The camera modes and the legend's fold, above the scene.
fn toolbar(ui: &mut egui::Ui, view: &mut SceneView) {
    // Wrapped: in a narrow tile the buttons go on a second row rather than under the next tile.
    ui.horizontal_wrapped(|ui| {
        ui.label("Camera");
        for mode in CameraMode::ALL {
            if ui
                .selectable_label(view.mode == mode, mode.name())
                .on_hover_text(mode.help())
                .clicked()
            {
                view.mode = mode;
            }
        }
        ui.separator();
        let fold = if view.legend_open {
            "Hide layers"
        } else {
            "Show layers"
        };
        if ui
            .selectable_label(view.legend_open, fold)
            .on_hover_text("Show or hide the legend, which switches the scene's layers")
            .clicked()
        {
            view.legend_open = !view.legend_open;
        }
    });
}

/// Draws the scene and handles its interaction.
pub fn ui(ui: &mut egui::Ui, state: &AppState, view: &mut SceneView, commands: &mut Vec<Command>) {
    toolbar(ui, view);
    let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
    draw(ui, &response, &painter, state, view, Some(commands));
    if view.legend_open {
        legend::ui(ui, legend::area(view.rect), state, commands);
    }
}

/// The scene alone, filling `ui`: no toolbar, legend or pointer — a frame of a rendered video
/// (`crate::app::render`). The camera fits the whole push, so that the view holds still.
pub fn picture(ui: &mut egui::Ui, state: &AppState, view: &mut SceneView) {
    view.mode = CameraMode::FitAll;
    view.legend_open = false;
    let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::hover());
    draw(ui, &response, &painter, state, view, None);
}

/// The scene in `response`'s rectangle; with `commands`, answering the pointer too.
fn draw(
    ui: &egui::Ui,
    response: &egui::Response,
    painter: &egui::Painter,
    state: &AppState,
    view: &mut SceneView,
    commands: Option<&mut Vec<Command>>,
) {
    view.rect = response.rect;
    let painter = painter.with_clip_rect(view.rect);
    let palette = colors::of(ui.ctx());
    painter.rect_filled(view.rect, 0.0, palette.background);
    let Some((pose, robot, pusher_radius, outline)) = shown_scene(state) else {
        painter.text(
            view.rect.center(),
            egui::Align2::CENTER_CENTER,
            "Open recordings with File > Open, or drop them here",
            egui::FontId::proportional(16.0),
            palette.muted,
        );
        return;
    };
    let content = Content {
        pose,
        robot,
        pusher_radius,
        outline: outline.as_ref(),
        predictions: state.predictions(),
        gain: state.settings().layers.motion_gain,
        what_if: state.what_if().filter(|_| state.settings().layers.what_if),
    };
    if let Some(commands) = commands {
        let markers = markers(state, view, &content);
        let projection = view.projection();
        let grips = Grips::of(state, &projection, &content.pose, content.robot);
        let drive_goal = (content.outline).and_then(|o| drive_goal::handles(state, &projection, o));
        interaction::handle(
            ui,
            response,
            state,
            view,
            &projection,
            &content.pose,
            (&markers, grips.as_ref(), drive_goal.as_ref()),
            commands,
        );
    }
    aim(state, view, &content);
    let projection = view.projection();
    draw_layers(&painter, state, view, &projection, &content, response);
    if let Some(grips) = Grips::of(state, &projection, &content.pose, content.robot) {
        let arrow = match view.drag {
            Some(Drag::Sandbox(Grab::Arrow(from))) => view.arrow_to.map(|to| (from, to)),
            _ => None,
        };
        let hot = match view.drag {
            Some(Drag::Sandbox(grab)) => Some(grab),
            _ => response
                .hover_pos()
                .and_then(|p| grips.grab(p, &projection))
                .filter(|g| !matches!(g, Grab::Arrow(_))),
        };
        sandbox::draw(&painter, state, &projection, &grips, arrow, hot);
    }
    if let Some(outline) = content.outline {
        drive_goal::draw(&painter, state, &projection, outline, view, response);
    }
    if view.drag.is_none() {
        hover::say_what_is_under(response, state, &projection, &content);
    }
}

/// What the scene shows: the object's pose, the pusher and its radius, the outline — at the
/// frame shown of the recording shown, or a sandbox's object resting before its first push.
fn shown_scene(state: &AppState) -> Option<(Pose2, Point2<f64>, f64, Option<Outline>)> {
    match state.recording() {
        Some(recording) => {
            let frame = recording.trajectory.frames.get(state.frame())?;
            Some((
                frame.object,
                frame.robot,
                recording.setting.pusher_radius,
                recording.setting.object.outline().ok(),
            ))
        }
        None => {
            let sandbox = state.sandbox()?.sandbox();
            let sim = &sandbox.mystery().sim;
            Some((
                sandbox.object_pose(),
                sandbox.pusher(),
                sim.pusher_radius,
                Some(sim.outline.clone()),
            ))
        }
    }
}

/// Where the COM markers are drawn this frame (with last frame's camera: what the user sees).
fn markers(state: &AppState, view: &SceneView, content: &Content<'_>) -> Markers {
    let projection = view.projection();
    let at = |com: [f64; 2]| projection.to_screen(content.pose.point_in_world(Point2::from(com)));
    let com_label = state
        .label_target()
        .filter(|t| {
            state.settings().layers.com_label && state.labels().read_only_reason(t).is_none()
        })
        .and_then(|t| state.labels().labels_of(&t).and_then(|l| l.meta.com_offset));
    Markers {
        com: state
            .theta()
            .filter(|_| state.settings().layers.com_estimated && !state.estimate_hidden())
            .map(|t| at(t.com_offset)),
        com_label: com_label.map(at),
    }
}

/// Points the camera for this frame: a new recording is framed afresh; following keeps the object
/// and its target footprints in view; fitting shows the whole push.
fn aim(state: &AppState, view: &mut SceneView, content: &Content<'_>) {
    let viewport = view.viewport();
    let object_size = content.outline.map_or(0.05, Outline::size);
    let whole_push = state
        .overview()
        .bounds
        .map(|(min, max)| WorldBox { min, max }.grown(0.8 * object_size));
    let Some(object) = content.footprint_box(&content.pose) else {
        return;
    };
    let disc = WorldBox::around([content.robot]).map(|b| b.grown(content.pusher_radius));
    let mut target = disc.map_or(object, |d| object.union(d));
    // Only where the targets are matters here, not their colours.
    for Target { pose, .. } in content.targets(state, &colors::DARK) {
        if let Some(footprint) = content.footprint_box(&pose) {
            target = target.union(footprint);
        }
    }
    // While a student drags a sandbox handle the world holds still under their hand: a camera
    // that followed the object would move the point the pusher heads for, and it would chase on.
    if matches!(view.drag, Some(Drag::Sandbox(_) | Drag::DriveGoal(_))) {
        view.framed = state.session().selected;
        return;
    }
    if view.framed != state.session().selected {
        view.framed = state.session().selected;
        view.camera = match (view.mode, whole_push) {
            (CameraMode::Follow, _) | (_, None) => {
                Camera::fitting(target.grown(object_size), viewport)
            }
            (_, Some(whole)) => Camera::fitting(whole, viewport),
        };
    }
    match view.mode {
        CameraMode::Follow => view
            .camera
            .follow(target.grown(0.1 * object_size), object, viewport),
        CameraMode::FitAll => {
            if let Some(whole) = whole_push {
                view.camera = Camera::fitting(whole, viewport);
            }
        }
        CameraMode::Free => {}
    }
}

/// Everything drawn, back to front.
fn draw_layers(
    painter: &egui::Painter,
    state: &AppState,
    view: &SceneView,
    projection: &Projection,
    content: &Content<'_>,
    response: &egui::Response,
) {
    let palette = colors::of(painter.ctx());
    let layers = &state.settings().layers;
    if layers.grid {
        draw::grid(painter, projection, view.rect);
    }
    if layers.robot_path {
        draw::path(painter, projection, &state.overview().robot_path);
    }
    if layers.trails
        && let Some(recording) = state.recording()
    {
        draw::trails(
            painter,
            projection,
            &recording.trajectory.frames,
            state.frame(),
        );
    }
    footprints(painter, state, projection, content, palette);
    draw::pusher(painter, projection, content.robot, content.pusher_radius);
    if layers.contact
        && let Some(p) = &content.predictions
    {
        draw::contact(
            painter,
            projection,
            &content.pose,
            &p.online.prediction,
            content.gain,
        );
    }
    if layers.com_true
        && let Some(com) = state.recording().and_then(|r| r.setting.com_offset)
    {
        draw::true_com(
            painter,
            projection.to_screen(content.pose.point_in_world(Point2::from(com))),
        );
    }
    if layers.com_best
        && let Some(run) = state.run()
        && let Some(fit) = state.best_fit().result_for(run).and_then(|r| r.fit)
    {
        let at = content
            .pose
            .point_in_world(Point2::from(fit.theta.com_offset));
        draw::best_com(painter, projection.to_screen(at));
    }
    if layers.next_pushes {
        next_pushes(painter, state, projection, content);
    }
    if layers.com_ellipse
        && !state.estimate_hidden()
        && let (Some(theta), Some(run)) = (state.theta(), &state.run())
    {
        let (axes, angle) = run.spread_at(state.frame()).ellipse_95();
        draw::com_ellipse(
            painter,
            projection,
            &content.pose,
            content.outline,
            theta.com_offset,
            axes,
            angle,
        );
    }
    markers_to_grab(painter, state, view, content, response);
}

/// The object's footprints: where it is now, its what-if rollout, and the targets of the layers on.
fn footprints(
    painter: &egui::Painter,
    state: &AppState,
    projection: &Projection,
    content: &Content<'_>,
    palette: &Palette,
) {
    let Some(outline) = content.outline else {
        return;
    };
    if state.settings().layers.true_now {
        draw::footprint(
            painter,
            projection,
            outline,
            &content.pose,
            FootprintStyle::measured_now(palette),
        );
    }
    if let (Some(rollout), Some(recording)) = (&content.what_if, state.recording()) {
        draw::what_if(painter, projection, outline, rollout, &recording.trajectory);
    }
    if let Some((goal, step)) = state.controller_here() {
        plan::goal(
            painter,
            projection,
            outline,
            &goal.pose,
            "where the push ends",
        );
        plan::plan(painter, projection, outline, step);
    }
    if let Some(drive) = state.live_drive_shown() {
        let driving = drive.driving();
        if driving.has_planned() {
            plan::plan(painter, projection, outline, driving.plan());
        }
    }
    for Target { pose, style, .. } in content.targets(state, palette) {
        draw::footprint(painter, projection, outline, &pose, style);
    }
}

/// The next pushes suggested for this object, as arrows on it numbered from the best.
fn next_pushes(
    painter: &egui::Painter,
    state: &AppState,
    projection: &Projection,
    content: &Content<'_>,
) {
    if let (Some(run), Some(outline)) = (state.run(), content.outline)
        && let Some(result) = state.next_push().result_for(run)
    {
        // Drawn worst first, so the best lies on top where arrows cross.
        let best = result.ranking.suggestions.iter().take(next_push::ARROWS);
        let shown: Vec<_> = best
            .enumerate()
            .filter_map(|(i, s)| Some((i, s.shape?)))
            .collect();
        for (i, shape) in shown.into_iter().rev() {
            let length = shape
                .length_m
                .clamp(0.3 * outline.size(), 0.8 * outline.size());
            draw::next_push(painter, projection, &content.pose, &shape, length, i + 1);
        }
    }
}

/// The markers where the user can grab them, highlighted under the pointer.
fn markers_to_grab(
    painter: &egui::Painter,
    state: &AppState,
    view: &SceneView,
    content: &Content<'_>,
    response: &egui::Response,
) {
    let markers = markers(state, view, content);
    let pointer = response.hover_pos();
    if let Some(at) = markers.com_label {
        let hot = markers.hot(Drag::ComLabel, pointer, view);
        draw::com_label(painter, at, hot);
        if hot {
            response.ctx.set_cursor_icon(egui::CursorIcon::Grab);
        }
    }
    if let Some(at) = markers.com {
        let hot = markers.hot(Drag::Com, pointer, view);
        draw::estimated_com(painter, at, hot);
        if hot {
            response.ctx.set_cursor_icon(egui::CursorIcon::Grab);
        }
    }
}
