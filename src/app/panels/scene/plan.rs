//! The controller's step drawn: the object's predicted arc along the push it chose (with the
//! outline where the arc ends) and the pusher's way round to that push. The sandbox's Push to goal
//! draws it while the controller pushes; on a replayed push, the layer "What would the controller
//! do here" draws it from the frame shown, with the goal it heads for: where the push ended.

use eframe::egui::{self, Pos2, Stroke, Vec2};
use pushlab_core::control::Plan;
use pushlab_core::geometry::{Outline, Pose2};

use super::camera::Projection;
use crate::app::colors;

/// The outline at `pose`, closed, on screen.
fn ring(projection: &Projection, outline: &Outline, pose: &Pose2) -> Vec<Pos2> {
    let mut ring: Vec<Pos2> = (outline.vertices().iter())
        .map(|v| projection.to_screen(pose.point_in_world(*v)))
        .collect();
    if let Some(&first) = ring.first() {
        ring.push(first);
    }
    ring
}

/// The plan's arc, the outline where it ends, and the pusher's way (dashed).
pub fn plan(painter: &egui::Painter, projection: &Projection, outline: &Outline, plan: &Plan) {
    let palette = colors::of(painter.ctx());
    let path: Vec<Pos2> = (plan.predicted.iter())
        .map(|p| projection.to_screen(p.position))
        .collect();
    painter.add(egui::Shape::line(
        path,
        Stroke::new(2.5, palette.online.gamma_multiply(0.9)),
    ));
    if let Some(end) = plan.predicted.last() {
        painter.add(egui::Shape::line(
            ring(projection, outline, end),
            Stroke::new(1.5, palette.online.gamma_multiply(0.6)),
        ));
    }
    if plan.way.len() > 1 {
        let way: Vec<Pos2> = plan.way.iter().map(|p| projection.to_screen(*p)).collect();
        painter.extend(egui::Shape::dashed_line(
            &way,
            Stroke::new(1.5, palette.robot.gamma_multiply(0.7)),
            6.0,
            4.0,
        ));
    }
}

/// A goal's ghost: the outline at `goal`, dashed, named by `label` beside its centre.
pub fn goal(
    painter: &egui::Painter,
    projection: &Projection,
    outline: &Outline,
    goal: &Pose2,
    label: &str,
) {
    let color = colors::of(painter.ctx()).suggestion;
    painter.extend(egui::Shape::dashed_line(
        &ring(projection, outline, goal),
        Stroke::new(2.0, color),
        8.0,
        5.0,
    ));
    painter.text(
        projection.to_screen(goal.position) + Vec2::new(12.0, 12.0),
        egui::Align2::LEFT_TOP,
        label,
        egui::FontId::proportional(14.0),
        color,
    );
}
