//! The scene: a top view of the table in metres, with the robot, the object's true and predicted
//! footprints, the COM estimates and the contact. Pan by dragging, zoom with the wheel; drag the
//! orange COM marker to steer the COM offset, and the magenta diamond to move the recording's COM label.

use eframe::egui::{self, Color32, Pos2, Rect, Sense, Shape, Stroke, Vec2};
use nalgebra::{Point2, Vector2};
use pushlab_core::geometry::{Outline, Pose2};
use pushlab_core::labels::MetaField;
use pushlab_core::model::{ObjectMotion, Prediction};

use crate::app::colors;
use crate::app::state::labels::LabelAction;
use crate::app::state::layers::Layers;
use crate::app::state::session::RecordingId;
use crate::app::state::{AppState, Command};

/// Frames of history drawn as a fading trail.
const TRAIL_FRAMES: usize = 120;
/// Pick radius of the COM marker, points.
const COM_PICK_RADIUS: f32 = 10.0;

/// The camera and the drag in progress.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneView {
    /// World point at the centre of the view, metres.
    centre: [f64; 2],
    /// Points per metre.
    scale: f32,
    /// The recording the camera was fitted to; a new selection refits.
    fitted_to: Option<RecordingId>,
    /// Whether the COM marker is being dragged.
    dragging_com: bool,
    /// Whether the COM label (the recording's labelled COM) is being dragged.
    dragging_com_label: bool,
    /// Where the scene was drawn last frame, screen points (for PNG export and tests).
    rect: Rect,
}

impl Default for SceneView {
    fn default() -> Self {
        Self {
            centre: [0.0, 0.0],
            scale: 2000.0,
            fitted_to: None,
            dragging_com: false,
            dragging_com_label: false,
            rect: Rect::NOTHING,
        }
    }
}

impl SceneView {
    /// Where the scene was drawn last frame, screen points.
    pub fn rect(&self) -> Rect {
        self.rect
    }

    /// Where the world point `world` (metres) is drawn when the scene fills `rect`.
    pub fn to_screen(&self, rect: Rect, world: Point2<f64>) -> Pos2 {
        self.camera(rect).to_screen(world)
    }

    /// The world point (metres) under the screen point `screen` when the scene fills `rect`.
    pub fn to_world(&self, rect: Rect, screen: Pos2) -> Point2<f64> {
        self.camera(rect).to_world(screen)
    }

    fn camera(&self, rect: Rect) -> Camera {
        Camera {
            rect,
            centre: self.centre,
            scale: self.scale,
        }
    }
}

/// Maps world metres to screen points and back (y up in the world, down on the screen).
#[derive(Clone, Copy)]
struct Camera {
    rect: Rect,
    centre: [f64; 2],
    scale: f32,
}

impl Camera {
    fn to_screen(self, p: Point2<f64>) -> Pos2 {
        let c = self.rect.center();
        Pos2::new(
            c.x + ((p.x - self.centre[0]) as f32) * self.scale,
            c.y - ((p.y - self.centre[1]) as f32) * self.scale,
        )
    }

    fn to_world(self, p: Pos2) -> Point2<f64> {
        let c = self.rect.center();
        Point2::new(
            self.centre[0] + ((p.x - c.x) / self.scale) as f64,
            self.centre[1] - ((p.y - c.y) / self.scale) as f64,
        )
    }
}

/// Draws the scene and handles its interaction.
pub fn ui(
    ui: &mut egui::Ui,
    state: &mut AppState,
    view: &mut SceneView,
    commands: &mut Vec<Command>,
) {
    let (response, painter) = ui.allocate_painter(ui.available_size(), Sense::click_and_drag());
    let rect = response.rect;
    view.rect = rect;
    painter.rect_filled(rect, 0.0, Color32::from_gray(22));

    let Some(recording) = state.recording() else {
        painter.text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "Open recordings with File > Open, or drop them here",
            egui::FontId::proportional(16.0),
            Color32::GRAY,
        );
        return;
    };
    let frames = &recording.trajectory.frames;
    let Some(frame_index) = (!frames.is_empty()).then(|| state.frame().min(frames.len() - 1))
    else {
        return;
    };
    let outline = recording.setting.object.outline().ok();

    if view.fitted_to != state.session.selected {
        fit(view, rect, recording, outline.as_ref());
        view.fitted_to = state.session.selected;
    }
    let frame = frames[frame_index];
    let pose = frame.object;
    let theta = state.theta();

    // Interaction: drag the COM marker, else pan; wheel/pinch zooms about the pointer.
    let mut camera = Camera {
        rect,
        centre: view.centre,
        scale: view.scale,
    };
    let com_screen = theta
        .filter(|_| state.layers.com_estimated)
        .map(|t| camera.to_screen(pose.point_in_world(Point2::from(t.com_offset))));
    let label_target = state.label_target();
    let com_label = label_target
        .as_ref()
        .filter(|t| state.layers.com_label && state.labels.read_only_reason(t).is_none())
        .and_then(|t| state.labels.labels_of(t))
        .and_then(|l| l.meta.com_offset);
    let com_label_screen =
        com_label.map(|c| camera.to_screen(pose.point_in_world(Point2::from(c))));
    // Pick by where the button went down: egui reports the drag only after the pointer has moved a
    // few points, and a quick drag is past the marker by then.
    if response.drag_started()
        && let Some(pointer) = ui
            .input(|i| i.pointer.press_origin())
            .or(response.interact_pointer_pos())
    {
        // The nearer of the two markers within reach is picked up.
        let reach = |marker: Option<Pos2>| {
            marker
                .map(|m| pointer.distance(m))
                .filter(|&d| d < COM_PICK_RADIUS)
        };
        match (reach(com_screen), reach(com_label_screen)) {
            (Some(a), Some(b)) if b < a => view.dragging_com_label = true,
            (Some(_), _) => view.dragging_com = true,
            (None, Some(_)) => view.dragging_com_label = true,
            (None, None) => {}
        }
        if view.dragging_com_label {
            commands.push(Command::Label(LabelAction::BeginGroup(
                "move the COM label".to_owned(),
            )));
        }
    }
    if response.dragged() {
        if view.dragging_com_label {
            if let (Some(pointer), Some(target)) = (response.interact_pointer_pos(), &label_target)
            {
                let com_in_object = pose.point_in_object(camera.to_world(pointer));
                commands.push(Command::Label(LabelAction::Edit(
                    pushlab_core::labels::Command::SetMeta {
                        recording: target.recording.clone(),
                        field: MetaField::ComOffset(Some([com_in_object.x, com_in_object.y])),
                    },
                )));
            }
        } else if view.dragging_com {
            if let (Some(pointer), Some(theta)) = (response.interact_pointer_pos(), theta) {
                let com_in_object = pose.point_in_object(camera.to_world(pointer));
                let mut steered = theta;
                steered.com_offset = [com_in_object.x, com_in_object.y];
                commands.push(Command::SetTheta(steered));
            }
        } else {
            let d = response.drag_delta();
            view.centre[0] -= (d.x / view.scale) as f64;
            view.centre[1] += (d.y / view.scale) as f64;
        }
    }
    if response.drag_stopped() {
        if view.dragging_com_label {
            commands.push(Command::Label(LabelAction::EndGroup));
        }
        view.dragging_com = false;
        view.dragging_com_label = false;
    }
    if response.hovered() {
        let (scroll, zoom) = ui.input(|i| (i.smooth_scroll_delta.y, i.zoom_delta()));
        let factor = zoom * (scroll / 400.0).exp();
        if (factor - 1.0).abs() > 1e-4
            && let Some(pointer) = response.hover_pos()
        {
            let before = camera.to_world(pointer);
            view.scale = (view.scale * factor).clamp(20.0, 200_000.0);
            camera.scale = view.scale;
            let after = camera.to_world(pointer);
            view.centre[0] += before.x - after.x;
            view.centre[1] += before.y - after.y;
        }
    }
    if response.double_clicked() {
        fit(view, rect, recording, outline.as_ref());
    }
    camera = Camera {
        rect,
        centre: view.centre,
        scale: view.scale,
    };
    let painter = painter.with_clip_rect(rect);
    let layers = state.layers.clone();

    if layers.grid {
        grid(&painter, &camera);
    }

    // Paths and trails.
    if layers.robot_path && frames.len() > 1 {
        let path = frames.iter().map(|f| camera.to_screen(f.robot)).collect();
        painter.add(Shape::line(
            path,
            Stroke::new(1.0, colors::ROBOT.gamma_multiply(0.25)),
        ));
    }
    if layers.trails {
        let start = frame_index.saturating_sub(TRAIL_FRAMES);
        for k in start..frame_index {
            let age = (frame_index - k) as f32 / TRAIL_FRAMES as f32;
            let alpha = (1.0 - age).powi(2) * 0.9;
            let (a, b) = (frames[k], frames[k + 1]);
            painter.line_segment(
                [camera.to_screen(a.robot), camera.to_screen(b.robot)],
                Stroke::new(2.5, colors::ROBOT.gamma_multiply(alpha)),
            );
            painter.line_segment(
                [
                    camera.to_screen(a.object.position),
                    camera.to_screen(b.object.position),
                ],
                Stroke::new(2.0, colors::TRUE.gamma_multiply(alpha * 0.7)),
            );
        }
    }

    let gain = layers.motion_gain;
    let step = state.current_step();
    if let Some(outline) = &outline {
        if layers.true_now {
            footprint(&painter, &camera, outline, &pose, colors::TRUE, true, false);
        }
        if layers.true_target
            && let Some(sample) = state.run.as_ref().and_then(|r| r.sample(frame_index))
        {
            let target = exaggerated(&pose, &sample.target, gain);
            footprint(
                &painter,
                &camera,
                outline,
                &target,
                colors::TRUE,
                false,
                true,
            );
        }
        if layers.predicted_fixed
            && let Some(fixed) = state.run.as_ref().and_then(|r| r.fixed().get(frame_index))
        {
            let predicted = exaggerated(&pose, &fixed.prediction.motion, gain);
            footprint(
                &painter,
                &camera,
                outline,
                &predicted,
                colors::FIXED,
                false,
                false,
            );
        }
        if layers.predicted_physics
            && let Some(prediction) = state.physics_prediction()
        {
            let predicted = exaggerated(&pose, &prediction.motion, gain);
            footprint(
                &painter,
                &camera,
                outline,
                &predicted,
                colors::PHYSICS,
                false,
                false,
            );
        }
        if layers.predicted_pure_nn
            && let (Some(model), Some(sample)) = (
                &state.models.pure_nn,
                state.run.as_ref().and_then(|r| r.sample(frame_index)),
            )
        {
            let prediction = model.predict(&sample.input);
            let predicted = exaggerated(&pose, &prediction.motion, gain);
            footprint(
                &painter,
                &camera,
                outline,
                &predicted,
                colors::PURE_NN,
                false,
                false,
            );
        }
        if layers.predicted_online
            && let Some(step) = &step
        {
            let predicted = exaggerated(&pose, &step.prediction.motion, gain);
            footprint(
                &painter,
                &camera,
                outline,
                &predicted,
                colors::ONLINE,
                false,
                false,
            );
        }
    }

    // The robot disc.
    let robot = camera.to_screen(frame.robot);
    let radius = (recording.setting.pusher_radius as f32 * camera.scale).max(3.0);
    painter.circle(
        robot,
        radius,
        colors::ROBOT.gamma_multiply(0.35),
        Stroke::new(2.0, colors::ROBOT),
    );

    if layers.contact
        && let Some(step) = &step
    {
        contact(&painter, &camera, &pose, &step.prediction, gain);
    }
    if layers.com_true
        && let Some(com) = recording.setting.com_offset
    {
        let p = camera.to_screen(pose.point_in_world(Point2::from(com)));
        let s = 7.0;
        let stroke = Stroke::new(2.0, colors::TRUE);
        painter.line_segment([p - Vec2::splat(s), p + Vec2::splat(s)], stroke);
        painter.line_segment([p + Vec2::new(-s, s), p + Vec2::new(s, -s)], stroke);
    }
    if let Some(p) = com_label_screen {
        let hot = view.dragging_com_label
            || response
                .hover_pos()
                .is_some_and(|h| h.distance(p) < COM_PICK_RADIUS);
        let s = if hot { 8.0 } else { 6.5 };
        let diamond = vec![
            p + Vec2::new(0.0, -s),
            p + Vec2::new(s, 0.0),
            p + Vec2::new(0.0, s),
            p + Vec2::new(-s, 0.0),
        ];
        painter.add(Shape::convex_polygon(
            diamond,
            colors::COM_LABEL,
            Stroke::new(1.5, Color32::BLACK),
        ));
        if hot {
            ui.ctx().set_cursor_icon(egui::CursorIcon::Grab);
        }
    }
    if layers.com_estimated
        && let Some(theta) = theta
    {
        let p = camera.to_screen(pose.point_in_world(Point2::from(theta.com_offset)));
        let hot = view.dragging_com
            || response
                .hover_pos()
                .is_some_and(|h| h.distance(p) < COM_PICK_RADIUS);
        painter.circle(
            p,
            if hot { 7.0 } else { 5.5 },
            colors::ONLINE,
            Stroke::new(1.5, Color32::BLACK),
        );
        if hot {
            ui.ctx().set_cursor_icon(egui::CursorIcon::Grab);
        }
    }

    legend(ui, rect, &mut state.layers);
}

/// The object pose reached by `motion` from `pose`, with the motion multiplied by `gain`.
fn exaggerated(pose: &Pose2, motion: &ObjectMotion, gain: f64) -> Pose2 {
    pose.moved_by(
        Vector2::new(motion.translation[0], motion.translation[1]) * gain,
        motion.rotation * gain,
    )
}

fn footprint(
    painter: &egui::Painter,
    camera: &Camera,
    outline: &Outline,
    pose: &Pose2,
    color: Color32,
    filled: bool,
    dashed: bool,
) {
    let points: Vec<Pos2> = outline
        .vertices()
        .iter()
        .map(|v| camera.to_screen(pose.point_in_world(*v)))
        .collect();
    if dashed {
        let mut closed = points.clone();
        closed.push(points[0]);
        painter.extend(Shape::dashed_line(
            &closed,
            Stroke::new(1.5, color),
            6.0,
            4.0,
        ));
    } else {
        let fill = if filled {
            color.gamma_multiply(0.12)
        } else {
            Color32::TRANSPARENT
        };
        painter.add(Shape::convex_polygon(points, fill, Stroke::new(2.0, color)));
    }
    // The object's x axis, so that rotation is visible on symmetric shapes.
    let centre = camera.to_screen(pose.position);
    let axis = camera.to_screen(pose.point_in_world(Point2::new(outline.size() * 0.15, 0.0)));
    painter.line_segment([centre, axis], Stroke::new(1.0, color.gamma_multiply(0.7)));
}

fn contact(
    painter: &egui::Painter,
    camera: &Camera,
    pose: &Pose2,
    prediction: &Prediction,
    gain: f64,
) {
    let Some(c) = prediction.contact else {
        return;
    };
    let c_world = pose.point_in_world(Point2::from(c));
    let p = camera.to_screen(c_world);
    painter.circle_filled(p, 4.0, colors::CONTACT);
    if let Some(u) = prediction.contact_motion {
        let u_world = pose.vector_in_world(Vector2::new(u[0], u[1])) * gain;
        let tip = camera.to_screen(c_world + u_world);
        painter.arrow(p, tip - p, Stroke::new(2.0, colors::CONTACT));
    }
}

/// Fits the camera to the robot path and the object's positions, with a margin of one object size.
fn fit(
    view: &mut SceneView,
    rect: Rect,
    recording: &pushlab_core::recording::Recording,
    outline: Option<&Outline>,
) {
    let frames = &recording.trajectory.frames;
    let margin = outline.map_or(0.05, |o| o.size()) * 0.8;
    let (mut min, mut max) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for f in frames {
        for p in [f.robot, f.object.position] {
            min = [min[0].min(p.x), min[1].min(p.y)];
            max = [max[0].max(p.x), max[1].max(p.y)];
        }
    }
    if !(min[0].is_finite() && max[0].is_finite()) {
        return;
    }
    view.centre = [(min[0] + max[0]) / 2.0, (min[1] + max[1]) / 2.0];
    let width = (max[0] - min[0] + 2.0 * margin).max(0.01);
    let height = (max[1] - min[1] + 2.0 * margin).max(0.01);
    let scale = (rect.width() as f64 / width).min(rect.height() as f64 / height);
    if scale.is_finite() && scale > 0.0 {
        view.scale = (scale as f32).clamp(20.0, 200_000.0);
    }
}

/// A metres grid whose spacing follows the zoom: minor lines 20–200 points apart, every tenth major.
fn grid(painter: &egui::Painter, camera: &Camera) {
    let rect = camera.rect;
    let mut spacing = 1e-3_f64;
    while (spacing as f32) * camera.scale < 20.0 {
        spacing *= 10.0;
    }
    let (lo, hi) = (
        camera.to_world(rect.left_bottom()),
        camera.to_world(rect.right_top()),
    );
    let label_font = egui::FontId::proportional(10.0);
    for axis in 0..2 {
        let (from, to) = if axis == 0 {
            (lo.x, hi.x)
        } else {
            (lo.y, hi.y)
        };
        let first = (from / spacing).floor() as i64;
        let last = (to / spacing).ceil() as i64;
        if last - first > 400 {
            continue;
        }
        for i in first..=last {
            let value = i as f64 * spacing;
            let major = i.rem_euclid(10) == 0;
            let color = if major {
                colors::GRID_MAJOR
            } else {
                colors::GRID
            };
            let (a, b) = if axis == 0 {
                let x = camera.to_screen(Point2::new(value, 0.0)).x;
                (Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom()))
            } else {
                let y = camera.to_screen(Point2::new(0.0, value)).y;
                (Pos2::new(rect.left(), y), Pos2::new(rect.right(), y))
            };
            painter.line_segment([a, b], Stroke::new(1.0, color));
            if major {
                let text = format_metres(value);
                let (pos, align) = if axis == 0 {
                    (
                        Pos2::new(a.x + 3.0, rect.bottom() - 3.0),
                        egui::Align2::LEFT_BOTTOM,
                    )
                } else {
                    (
                        Pos2::new(rect.right() - 3.0, a.y - 2.0),
                        egui::Align2::RIGHT_BOTTOM,
                    )
                };
                painter.text(
                    pos,
                    align,
                    text,
                    label_font.clone(),
                    colors::GRID_MAJOR.gamma_multiply(1.6),
                );
            }
        }
    }
}

fn format_metres(value: f64) -> String {
    if value.abs() < 1e-12 {
        "0 m".to_owned()
    } else {
        format!("{value:.3} m")
    }
}

/// The legend, which doubles as the layer toggles: each entry is a checkbox in its layer's colour.
fn legend(ui: &mut egui::Ui, rect: Rect, layers: &mut Layers) {
    let area = Rect::from_min_size(rect.min + Vec2::splat(8.0), Vec2::new(230.0, 360.0));
    let mut child = ui.new_child(egui::UiBuilder::new().max_rect(area));
    egui::Frame::popup(child.style())
        .fill(Color32::from_black_alpha(190))
        .show(&mut child, |ui| {
            ui.spacing_mut().item_spacing.y = 1.0;
            let entries: [(&mut bool, &str, Color32); 12] = [
                (&mut layers.true_now, "True footprint now", colors::TRUE),
                (
                    &mut layers.true_target,
                    "True footprint at target (dashed)",
                    colors::TRUE,
                ),
                (
                    &mut layers.predicted_online,
                    "Predicted: online θ",
                    colors::ONLINE,
                ),
                (
                    &mut layers.predicted_fixed,
                    "Predicted: fixed θ(0)",
                    colors::FIXED,
                ),
                (
                    &mut layers.predicted_pure_nn,
                    "Predicted: pure NN",
                    colors::PURE_NN,
                ),
                (
                    &mut layers.predicted_physics,
                    "Predicted: physics only",
                    colors::PHYSICS,
                ),
                (
                    &mut layers.com_estimated,
                    "Estimated COM (drag me)",
                    colors::ONLINE,
                ),
                (&mut layers.com_true, "True COM ×", colors::TRUE),
                (
                    &mut layers.com_label,
                    "Labelled COM, diamond (drag me)",
                    colors::COM_LABEL,
                ),
                (&mut layers.contact, "Contact c and u_c", colors::CONTACT),
                (&mut layers.robot_path, "Robot path", colors::ROBOT),
                (&mut layers.trails, "Trails", colors::ROBOT),
            ];
            for (on, label, color) in entries {
                ui.checkbox(on, egui::RichText::new(label).color(color).small());
            }
            ui.checkbox(
                &mut layers.grid,
                egui::RichText::new("Grid (metres)").small(),
            );
            ui.add(
                egui::Slider::new(&mut layers.motion_gain, 1.0..=50.0)
                    .logarithmic(true)
                    .text(egui::RichText::new("Motion ×").small()),
            )
            .on_hover_text("Target poses are drawn with their motion from now multiplied by this");
        });
}
